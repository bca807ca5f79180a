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

// Where a budgeted splatting stopped within a light view: the splatting level, and the first
// sample (gl_VertexID) of that level not yet drawn.
struct SplatCursor {
  int level = 0;
  GLint first = 0;
};

// The splatting budget of one render (ssSetSplatBudget, docs/VIEWPORT.md, "Progressive splatting"):
// at most `fragments` splatting fragment invocations, kept by measuring. Samples are drawn in
// chunks: in each light view the first of one sample, each next at most twice the last (and at
// most kProbe samples until one drew a fragment), and no larger than what fits in the budget left
// at twice the densest chunk's fragments per sample so far in the render. A render draws at least
// one sample, so that it always advances. A chunk far denser than those before it can still pass
// the budget: it is kept by measuring, not by a bound (docs/VIEWPORT.md).
struct SplatBudget {
  static constexpr GLint kProbe = 16;
  uint64_t fragments = 0;
  uint64_t spent = 0;
  double density = 0.0;  // the most fragments per sample of a chunk so far
  GLint lastChunk = 0;   // samples, in this light view
  bool viewMeasured = false;  // a chunk of this light view drew a fragment
  bool drewAny = false;
  uint64_t left() const { return spent < fragments ? fragments - spent : 0; }
};

class Splatting {
 public:
  // levels > 1: multiresolution splatting into that many exitance levels.
  void resize(int width, int height, int levels = 1);
  void clear();  // the exitance levels and the selection counters
  // Adds the selected lit translucent samples of `irradiance` to the exitance
  // buffers (each level its range of distances), each level in its own
  // profiler span, and counts the samples selected per irradiance level.
  // With a budget: from `cursor` on, in chunks while the budget lasts; `cursor` is left where it
  // stopped. Returns whether every sample of the view has been drawn.
  bool splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
             const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
             StageProfiler& profiler, SplatCursor* cursor = nullptr, SplatBudget* budget = nullptr);
  // The samples selected per irradiance level since clear(), added to
  // `selectedPerLevel`; returns their sum. Reads the counters back once a frame.
  uint64_t readSelectionCounts(uint64_t selectedPerLevel[8]);
  // Eq. 17: gathers the levels into level 0, coarse to fine. keepLevels: into copies of the
  // levels, which stay as splatted for the next chunks of a budgeted render.
  void accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                  StageProfiler& profiler, bool keepLevels = false);
  GLuint exitance() const { return (gathered_ ? gatheredLevels_ : exitance_).front().id(); }
  int levels() const { return int(exitance_.size()); }
  // The samples (of every irradiance level) of the last view splat() drew.
  GLint lastSampleCount() const { return lastSampleCount_; }

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
  // accumulate(keepLevels): the levels' copies the accumulation wrote, and whether exitance() is theirs.
  std::vector<gl::Texture> gatheredLevels_;
  std::vector<gl::Framebuffer> gatheredFramebuffers_;
  bool gathered_ = false;
  GLint lastSampleCount_ = 0;
  gl::Buffer counts_;  // SelectionCounts (splat.vert)
};

}  // namespace subsplat
