// Splatting (paper sec. 4, step 3): irradiance samples splatted as screen
// quads into the exitance buffer B(x_o), eq. 5 / 12. BRUTE splats every texel
// of the finest irradiance level (Shah et al. 2009).
#pragma once

#include "gl/gl.h"
#include "pipeline/buffers.h"

namespace subsplat {

// Which irradiance samples are splatted: levels == 1 takes every finest texel
// (BRUTE); more levels select adaptively (Algorithm 1, splat.vert).
struct Selection {
  int levels = 1;
  float z0 = 0.0f;     // depth-range threshold, scene units
  float alpha = 15.0f;
};

class Splatting {
 public:
  void resize(int width, int height);
  void clear();
  // Adds the selected lit translucent samples of `irradiance` to the exitance
  // buffer; adds the samples selected per level to `selectedPerLevel` and
  // returns the number of splats drawn.
  uint64_t splatLevel(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                      const SplattingBuffer& splatting, GLuint kernelTable, const Selection& selection,
                      uint64_t selectedPerLevel[8]);
  GLuint exitance() const { return exitance_.id(); }

 private:
  int width_ = 0, height_ = 0;
  gl::Program program_;
  gl::VertexArray empty_;
  gl::Texture exitance_;
  gl::Framebuffer framebuffer_;
  gl::Buffer counts_;  // SelectionCounts (splat.vert)
};

class Shading {
 public:
  void resize(int width, int height);
  void clear();
  // Direct light of one light view (diffuse, specular, shadows).
  void directLighting(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                      const SplattingBuffer& splatting);
  // Eq. 7 and the background into `target` (RGBA32F, width x height).
  void finalShading(const Scene& scene, const SplattingBuffer& splatting, GLuint exitance,
                    const float background[4]);
  GLuint result() const { return result_.id(); }
  GLuint resultFramebuffer() const { return resultFramebuffer_.id(); }

 private:
  int width_ = 0, height_ = 0;
  gl::Program directProgram_, finalProgram_;
  gl::VertexArray empty_;
  gl::Texture direct_, result_;
  gl::Framebuffer directFramebuffer_, resultFramebuffer_;
};

}  // namespace subsplat
