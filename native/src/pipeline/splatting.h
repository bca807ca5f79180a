// Splatting (paper sec. 4, step 3): irradiance samples splatted as screen
// quads into the exitance buffer B(x_o), eq. 5 / 12. BRUTE splats every texel
// of the finest irradiance level (Shah et al. 2009).
#pragma once

#include "gl/gl.h"
#include "pipeline/accumulation.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/material_tables.h"
#include "pipeline/sample_selection.h"
#include "pipeline/splat_depth.h"
#include "pipeline/splatting_buffer.h"
#include "pipeline/stage_profiler.h"

#include <vector>

namespace subsplat {

// Where a budgeted splatting stopped within a light view: the splatting level, and the first
// sample (gl_VertexID) of that level not yet drawn.
struct SplatCursor {
  int level = 0;
  GLint first = 0;   // in the view's sample list (pipeline/sample_selection.h)
  bool counted = false;  // the view's selected samples were added to the frame's counts
  // A budgeted render's bound of each sample's fragments at each level of this view (splat.geom),
  // measured a slice at a time ahead of the cursor and kept while the view's renders go on.
  std::vector<std::vector<GLuint>> bounds;
};

// The splatting budget of one render (ssSetSplatBudget, docs/VIEWPORT.md, "Progressive splatting"):
// at most `fragments` splatting fragment invocations, kept by a bound. Before drawing a level from
// the cursor on, a pass without rasterisation writes each sample's bound (splat.geom), a slice at a
// time and kept for the view's next renders; the level is then drawn up to the last sample whose
// bound (with kSampleCost) still fits in what is left. A render draws at
// least one sample, so that it always advances (that one sample may pass a budget smaller than
// its own quad).
struct SplatBudget {
  // A sample's vertex and geometry work, charged once for measuring it and once for drawing it, in
  // fragment invocations: a redraw through samples that draw nothing at its level (whose distances
  // all fall to the other levels) is bounded too.
  static constexpr uint64_t kSampleCost = 8;
  static constexpr GLint kBoundsSlice = 32768, kMinSlice = 256;  // samples measured at a time
  uint64_t fragments = 0;
  uint64_t spent = 0;  // the bounds of what was drawn, and kSampleCost per sample measured or drawn
  bool drewAny = false;
  uint64_t left() const { return spent < fragments ? fragments - spent : 0; }
};

class Splatting {
 public:
  // levels > 1: multiresolution splatting into that many exitance levels.
  void resize(int width, int height, int levels = 1);
  void clear();  // the exitance levels and the selection counters
  // Each level's depth from the splatting buffer (SplatDepth), after clear() and before the first
  // splat(): splats then skip the pixels whose surface lies beyond their reach.
  void prepareDepth(const Scene& scene, const SplattingBuffer& splatting) { depth_.prepare(scene, splatting); }
  // Adds the selected lit translucent samples of `irradiance` to the exitance
  // buffers (each level its range of distances), each level in its own
  // profiler span, and counts the samples selected per irradiance level.
  // With a budget: each level from `cursor` on, as many samples as the budget leaves room for (one
  // draw per level); `cursor` is left where it stopped. Returns whether every sample of the view
  // has been drawn.
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
  // splat.frag by objects of several translucent profiles and TABULATED materials.
  gl::ProgramVariants programs_{"splat.vert", "splat.geom", "splat.frag"};
  gl::Program accumulateProgram_;
  gl::VertexArray empty_;
  std::vector<gl::Texture> exitance_;
  SplatDepth depth_;  // attached to framebuffers_
  std::vector<gl::Framebuffer> framebuffers_;
  // accumulate(keepLevels): the levels' copies the accumulation wrote, and whether exitance() is theirs.
  std::vector<gl::Texture> gatheredLevels_;
  std::vector<gl::Framebuffer> gatheredFramebuffers_;
  bool gathered_ = false;
  GLint lastSampleCount_ = 0;
  gl::Buffer bounds_;  // SplatBounds (splat.geom), one uint per sample
  size_t boundsCapacity_ = 0;
  SelectionCounts counts_;
  SampleList samples_;
};

}  // namespace subsplat
