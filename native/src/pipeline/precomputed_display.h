// PRECOMPUTED (docs/PRECOMPUTED.md): the relit transport of every object as the camera sees it,
// an exitance texture in the place of the splats' for the final shading.
#pragma once

#include <vector>

#include "gl/gl.h"
#include "precomputed/precomputed_transport.h"
#include "scene.h"

namespace subsplat {

class PrecomputedDisplay {
 public:
  void resize(int width, int height);
  // Draws each object's triangles, seen by `camera`, with their atlas's local response and their
  // vertices' global response; the nearest surface wins (the final shading reads the exitance only
  // where the camera's buffers show a translucent surface).
  void draw(const PrecomputedTransport& transport, const Scene& scene, const SsCameraDesc& camera);
  GLuint exitance() const { return exitance_.id(); }

 private:
  int width_ = 0, height_ = 0;
  gl::Program program_;
  gl::Texture exitance_, depth_;
  gl::Framebuffer framebuffer_;
  struct ObjectGpu {
    int width = 0, height = 0;
    size_t corners = 0;
    gl::Texture local;
    gl::Buffer vertices;
    gl::VertexArray array;
  };
  std::vector<ObjectGpu> objects_;
};

}  // namespace subsplat
