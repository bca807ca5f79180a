// Splatting (paper sec. 4, step 3): irradiance samples splatted as screen
// quads into the exitance buffer B(x_o), eq. 5 / 12. BRUTE splats every texel
// of the finest irradiance level (Shah et al. 2009).
#pragma once

#include "gl/gl.h"
#include "pipeline/buffers.h"
#include "pipeline/material_tables.h"
#include "pipeline/stage_profiler.h"

#include <vector>

namespace subsplat {

// Which irradiance samples are splatted: levels == 1 takes every finest texel
// (BRUTE); more levels select adaptively (Algorithm 1, splat.vert).
struct Selection {
  int levels = 1;
  float z0 = 0.0f;     // depth-range threshold, scene units
  float alpha = 15.0f;
};

// Eq. 17's weights.
struct Accumulation {
  float lambdaZ = 8.0f, lambdaM = 8.0f;
  float boundingDiameter = 1.0f;  // R_w
};

class Splatting {
 public:
  // levels > 1: multiresolution splatting into that many exitance levels.
  void resize(int width, int height, int levels = 1);
  void clear();  // the exitance levels and the selection counters
  // Adds the selected lit translucent samples of `irradiance` to the exitance
  // buffers (each level its range of distances), each level in its own
  // profiler span, and counts the samples selected per irradiance level.
  void splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
             const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
             StageProfiler& profiler);
  // The samples selected per irradiance level since clear(), added to
  // `selectedPerLevel`; returns their sum. Reads the counters back once a frame.
  uint64_t readSelectionCounts(uint64_t selectedPerLevel[8]);
  // Eq. 17: gathers the levels into level 0, coarse to fine.
  void accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                  StageProfiler& profiler);
  GLuint exitance() const { return exitance_.front().id(); }
  int levels() const { return int(exitance_.size()); }

  // Debug passes (SS_PASS_SELECTION, SS_PASS_LEVEL_EXITANCE), kept only while enabled.
  void setDebug(bool enabled);
  GLuint selection() const { return selection_.id(); }
  // Level k's exitance as splatted, before accumulation.
  GLuint levelExitance(int k) const { return levelCopies_.at(size_t(k)).id(); }

 private:
  void setSelectionUniforms(GLuint program, const Scene& scene, const LightView& view,
                            const IrradianceBuffer& irradiance, const SplattingBuffer& splatting,
                            const Selection& selection, GLint offsets[9]);
  bool debug_ = false;
  gl::Program selectionProgram_;
  gl::Texture selection_;
  gl::Framebuffer selectionFramebuffer_;
  std::vector<gl::Texture> levelCopies_;
  int width_ = 0, height_ = 0;
  gl::Program program_, accumulateProgram_;
  gl::VertexArray empty_;
  std::vector<gl::Texture> exitance_;
  std::vector<gl::Framebuffer> framebuffers_;
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
  GLuint resultFramebuffer() const { return resultFramebuffer_.id(); }

 private:
  int width_ = 0, height_ = 0;
  gl::Program directProgram_, finalProgram_;
  gl::VertexArray empty_;
  gl::Texture direct_, result_;
  gl::Framebuffer directFramebuffer_, resultFramebuffer_;
};

}  // namespace subsplat
