// The splatting levels' depth for the splat draws' depth test (splat_depth.frag). A splat's quad
// bounds the sphere its kernel reaches; splat.geom and transport_splat.geom put the quad at that
// sphere's far side, and with GL_GEQUAL against each pixel's surface depth the pixels whose surface
// lies beyond the sphere are skipped before their fragment shader runs. Every such pixel is farther
// from the sample than the splat reaches, so the shader would have discarded it: the images are the
// same, and a GPU with early depth testing runs fewer fragments (docs/SPLATTING.md, "Splats stop at
// their sphere's far side").
#pragma once

#include <vector>

#include "gl/gl.h"
#include "pipeline/splatting_buffer.h"
#include "scene.h"

namespace subsplat {

class SplatDepth {
 public:
  // One depth texture a splatting level (4 bytes a pixel), made again when the size changes.
  void resize(int width, int height, int levels);
  // Every splat passes (depth 0) until prepare().
  void clear();
  // Each level's surface depth from the splatting buffer, seen by the scene's camera.
  void prepare(const Scene& scene, const SplattingBuffer& splatting);
  GLuint texture(int level) const { return textures_.at(size_t(level)).id(); }
  float far() const { return far_; }  // the depths' scale (splat shaders' depthFar)
  // The splat draws' depth test, on and off.
  static void beginTest();
  static void endTest();

 private:
  int width_ = 0, height_ = 0;
  gl::Program program_;
  gl::VertexArray empty_;
  std::vector<gl::Texture> textures_;
  std::vector<gl::Framebuffer> framebuffers_;  // depth only, for clear() and prepare()
  float far_ = 1.0f;
};

}  // namespace subsplat
