// Splatting (paper sec. 4, step 3): irradiance samples splatted as screen
// quads into the exitance buffer B(x_o), eq. 5 / 12. BRUTE splats every texel
// of the finest irradiance level (Shah et al. 2009).
#pragma once

#include "gl/gl.h"
#include "pipeline/accumulation.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/material_tables.h"
#include "pipeline/sample_selection.h"
#include "pipeline/splatting_buffer.h"
#include "pipeline/stage_profiler.h"

#include <vector>

namespace subsplat {

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

}  // namespace subsplat
