// The splatting buffer (paper sec. 4, step 1): the surface seen from the
// camera (position, normal, material, texture colour and shading normal per pixel), and its median-depth
// hierarchy for multiresolution splatting.
#pragma once

#include "gl/gl.h"
#include "pipeline/pass_helpers.h"
#include "scene.h"

namespace subsplat {

class SplattingBuffer {
 public:
  // levels > 1: a median-depth hierarchy for multiresolution splatting.
  void resize(int width, int height, int levels = 1);
  void render(const Scene& scene, const GpuScene& gpu);
  void buildHierarchy(const SsCameraDesc& camera);
  int levels() const { return levels_; }
  GLuint positionObject() const { return positionObject_.id(); }
  GLuint normalMaterial() const { return normalMaterial_.id(); }
  // Level 0 only: the colour texture per pixel (1 without one) and the normal map's shading normal.
  GLuint albedo() const { return albedo_.id(); }
  GLuint shadingNormal() const { return shadingNormal_.id(); }

 private:
  int width_ = 0, height_ = 0, levels_ = 0;
  gl::ProgramVariants programs_{"mesh.vert", "", "splatting_buffer.frag"};  // by sceneVariant
  gl::Program reduceProgram_;
  gl::Texture positionObject_, normalMaterial_, albedo_, shadingNormal_, depth_;
  gl::Framebuffer framebuffer_;
};

}  // namespace subsplat
