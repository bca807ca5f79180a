// Anti-aliasing (docs/ANTIALIASING.md): a frame's samples after the first are not splatted; each
// takes the first sample's exitance at its own pixels' surface points.
#pragma once

#include <vector>

#include "gl/gl.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/splatting_buffer.h"
#include "scene.h"

namespace subsplat {

// The shadow inputs of every light view of a frame, kept for its samples after the first (which
// then draw no shadow map again), up to kBudgetBytes; a view past it is rendered again.
class ShadowCopies {
 public:
  static constexpr size_t kBudgetBytes = size_t(256) << 20;
  // Keeps view `index`'s inputs from `irradiance` if the budget allows (withSurface: the position
  // and normal too, for TABULATED materials); false when it does not.
  // shadow: the view's shadow map inputs (ShadowInputs' shadowDepth, shadowResolution).
  bool keep(size_t index, const ShadowInputs& shadow, bool withSurface);
  // The kept inputs of view `index`, or nullptr.
  const ShadowInputs* find(size_t index) const;
  // Forgets every view (their textures stay for the next frame's views of the same size).
  void reset() { kept_.clear(); }

 private:
  struct Copy {
    int resolution = 0, shadowResolution = 0;  // shadowResolution 0: the irradiance buffer's map
    bool withSurface = false, ownSoft = false;
    gl::Texture depth, position, normal, shadow, soft;
  };
  std::vector<Copy> copies_;
  std::vector<ShadowInputs> kept_;  // per view index, resolution 0 where not kept
};

class ExitanceReprojection {
 public:
  void resize(int width, int height);
  // The exitance `firstExitance` (of the first sample, seen by `first` into `firstBuffer`) at the
  // pixels of `sample`, seen by `camera` (reproject_exitance.frag).
  void reproject(const SsCameraDesc& first, const SplattingBuffer& firstBuffer, GLuint firstExitance,
                 const SsCameraDesc& camera, const SplattingBuffer& sample);
  GLuint exitance() const { return exitance_.id(); }

 private:
  int width_ = 0, height_ = 0;
  gl::Program program_;
  gl::VertexArray empty_;
  gl::Texture exitance_;
  gl::Framebuffer framebuffer_;
};

}  // namespace subsplat
