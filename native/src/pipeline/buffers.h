// Buffer generation (paper sec. 4, step 1): the irradiance buffer seen from a
// light view and the splatting buffer seen from the camera.
#pragma once

#include <glm/glm.hpp>

#include "gl/gl.h"
#include "pipeline/gpu_scene.h"
#include "pipeline/light_views.h"
#include "scene.h"
#include "util/camera.h"

namespace subsplat {

// Uniform helpers shared by the passes.
GLint uniform(GLuint program, const char* name);
void setLightUniforms(GLuint program, const LightView& view);
// Binds `texture` on a unit of the binding table (gl/bindings.h), which the shaders name, and
// no sampler object there (a host's sampler would override the texture's filtering).
void bindTexture(int unit, GLenum target, GLuint texture);

// Draws every mesh of the scene with `program` (mesh.vert) into the bound target.
void drawMeshes(const Scene& scene, const GpuScene& gpu, GLuint program, const glm::mat4& viewProj);

class IrradianceBuffer {
 public:
  // levels: 1 for BRUTE; the hierarchy's depth for the adaptive methods.
  // profileSplits: keep, per level-0 texel, where a second profile covers part
  // of it (heterogeneous scenes only; docs/HETEROGENEOUS.md).
  void resize(int resolution, int levels = 1, bool profileSplits = false);
  void render(const Scene& scene, const GpuScene& gpu, const LightView& view);
  // Builds levels 1 .. levels-1 and the min/max depth hierarchy from level 0.
  void buildHierarchy();
  int resolution() const { return resolution_; }
  int levels() const { return levels_; }
  // rg: min and max light depth under each texel, levels 1 .. levels-1
  // (level 0 is lightDepth()).
  GLuint depthRange() const { return depthRange_.id(); }
  GLuint positionMaterial() const { return positionMaterial_.id(); }
  GLuint fluxFootprint() const { return fluxFootprint_.id(); }
  GLuint normalObject() const { return normalObject_.id(); }
  GLuint lightDepth() const { return lightDepth_.id(); }
  // Every level, 0 unless resized with profileSplits: xyz the offset of the
  // second profile's part from the texel centre over the footprint sigma,
  // w = (its entry - the material's first) * 32 + its sixteenths of the texel.
  GLuint profileSplit() const { return profileSplit_.id(); }
  bool profileSplits() const { return profileSplits_; }

 private:
  int resolution_ = 0, levels_ = 0;
  bool profileSplits_ = false;
  gl::Program program_, reduceProgram_;
  gl::Texture positionMaterial_, fluxFootprint_, normalObject_, lightDepth_, depthRange_, depth_, profileSplit_;
  gl::Framebuffer framebuffer_;
};

class SplattingBuffer {
 public:
  // levels > 1: a median-depth hierarchy for multiresolution splatting.
  void resize(int width, int height, int levels = 1);
  void render(const Scene& scene, const GpuScene& gpu);
  void buildHierarchy(const SsCameraDesc& camera);
  int levels() const { return levels_; }
  GLuint positionObject() const { return positionObject_.id(); }
  GLuint normalMaterial() const { return normalMaterial_.id(); }

 private:
  int width_ = 0, height_ = 0, levels_ = 0;
  gl::Program program_, reduceProgram_;
  gl::Texture positionObject_, normalMaterial_, depth_;
  gl::Framebuffer framebuffer_;
};

// cameraPosition, cameraForward and orthographic as uniforms.
void setCameraUniforms(GLuint program, const SsCameraDesc& camera);

}  // namespace subsplat
