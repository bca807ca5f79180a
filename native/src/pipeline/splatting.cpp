#include "pipeline/splatting.h"

#include <algorithm>

#include "material/splat_kernel.h"

namespace subsplat {

void Splatting::resize(int width, int height, int levels) {
  if (!empty_) empty_ = gl::makeVertexArray();
  bool debugReady = !debug_ || (selection_ && levelCopies_.size() == size_t(levels));
  if (width == width_ && height == height_ && levels == int(exitance_.size()) && debugReady) return;
  width_ = height_ = 0;  // as in IrradianceBuffer::resize
  framebuffers_.clear();
  exitance_.clear();
  gatheredFramebuffers_.clear();
  gatheredLevels_.clear();
  gathered_ = false;
  levelCopies_.clear();
  selectionFramebuffer_ = gl::Framebuffer();
  selection_ = gl::Texture();
  depth_.resize(width, height, levels);
  for (int k = 0; k < levels; ++k) {
    exitance_.push_back(gl::makeTexture2D(GL_RGBA32F, std::max(width >> k, 1), std::max(height >> k, 1)));
    framebuffers_.push_back(gl::makeFramebuffer({exitance_.back().id()}, depth_.texture(k)));
    if (debug_)
      levelCopies_.push_back(gl::makeTexture2D(GL_RGBA32F, std::max(width >> k, 1), std::max(height >> k, 1)));
  }
  selection_ = gl::Texture();
  selectionFramebuffer_ = gl::Framebuffer();
  if (debug_) {
    if (!selectionProgram_)
      selectionProgram_ = gl::makeProgram("splat.vert", "selection_debug.geom", "selection_debug.frag");
    selection_ = gl::makeTexture2D(GL_RGBA32F, width, height);
    selectionFramebuffer_ = gl::makeFramebuffer({selection_.id()}, 0);
  }
  width_ = width;
  height_ = height;
}

void Splatting::setDebug(bool enabled) {
  if (enabled != debug_) width_ = height_ = 0;  // reallocate at the next resize
  debug_ = enabled;
}

void Splatting::clear() {
  const float zero[4] = {0, 0, 0, 0};
  for (const gl::Framebuffer& f : framebuffers_) {
    glBindFramebuffer(GL_FRAMEBUFFER, f.id());
    glClearBufferfv(GL_COLOR, 0, zero);
  }
  depth_.clear();
  if (selectionFramebuffer_) {
    glBindFramebuffer(GL_FRAMEBUFFER, selectionFramebuffer_.id());
    glClearBufferfv(GL_COLOR, 0, zero);
  }
  counts_.clear();
}

uint64_t Splatting::readSelectionCounts(uint64_t selectedPerLevel[8]) { return counts_.read(selectedPerLevel); }

bool Splatting::splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                      const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
                      StageProfiler& profiler, SplatCursor* cursor, SplatBudget* budget) {
  SplatCursor whole;
  SplatCursor& at = cursor ? *cursor : whole;
  profiler.begin(SS_STAGE_SPLATTING, StageProfiler::kSelection);
  samples_.build(scene, view, irradiance, splatting, selection, at.counted ? nullptr : &counts_);  // counts_: zeroed by clear(), summed over views
  profiler.end();
  at.counted = true;
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  SplatDepth::beginTest();  // pixels whose surface lies beyond a splat's reach (prepareDepth)
  GLuint p = programs_.get({{"PAIR_PROFILES", scene.heterogeneous()},
                            {"TRANSMISSION", scene.tabulated()},
                            {"FORWARD_SHIFT", scene.tabulated() && selection.forwardShift}});
  glUseProgram(p);
  GLint offsets[9];
  setSelectionUniforms(p, scene, view, irradiance, splatting, selection, offsets);
  glUniform1f(uniform(p, "depthFar"), depth_.far());
  glUniform1i(uniform(p, "forwardShifts"), selection.forwardShift ? 1 : 0);
  samples_.bind();
  glUniform2f(uniform(p, "kernelLog2Range"), float(SplatKernel::kMinLog2), float(SplatKernel::kMaxLog2));
  glUniform1f(uniform(p, "footprintReach"), float(SplatKernel::kFootprintReach));
  glUniform2f(uniform(p, "kernelTableSize"), float(SplatKernel::kSizeD), float(SplatKernel::kSizeA));
  glUniform2f(uniform(p, "minimalRadiusLog2T"), float(SplatKernel::kMinLog2T), float(SplatKernel::kMaxLog2T));
  glUniform1f(uniform(p, "kernelLayers"), float(kernels.layers));
  int splatLevels = int(exitance_.size());
  GLfloat heights[8] = {};
  for (int k = 0; k < splatLevels; ++k) heights[k] = float(std::max(height_ >> k, 1));
  glUniform1i(uniform(p, "splatLevels"), splatLevels);
  glUniform1fv(uniform(p, "levelHeight"), 8, heights);
  bindTexture(gl::UNIT_SPLAT_KERNELS, GL_TEXTURE_2D_ARRAY, kernels.kernels);
  bindTexture(gl::UNIT_MINIMAL_RADIUS, GL_TEXTURE_2D, kernels.minimalRadius);
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  glBindVertexArray(empty_.id());
  GLint total = budget ? samples_.count() : 0;  // only a budget draws ranges of the list
  lastSampleCount_ = total;
  bool done = true;
  for (; at.level < splatLevels && done; ++at.level) {
    int k = at.level;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    glUniform1i(uniform(p, "splatLevel"), k);
    glUniform2f(uniform(p, "viewportSize"), float(std::max(width_ >> k, 1)), float(std::max(height_ >> k, 1)));
    if (!budget) {
      profiler.begin(SS_STAGE_SPLATTING, k);
      samples_.draw();
      profiler.end();
      continue;
    }
    if (budget->drewAny && budget->left() == 0 && at.first < total) {
      done = false;
      break;
    }
    // The bounds of the level's samples (splat.geom), measured a slice at a time ahead of the
    // cursor and kept for the view's later renders; then as many samples as fit.
    if (at.bounds.size() != size_t(splatLevels)) at.bounds.assign(size_t(splatLevels), {});
    std::vector<GLuint>& levelBounds = at.bounds[size_t(k)];
    auto measure = [&](GLint first, GLint slice) {
      GLint end = std::min(total, first + slice), n = end - first;
      budget->spent += uint64_t(n) * SplatBudget::kSampleCost;
      size_t bytes = size_t(n) * sizeof(GLuint);
      if (bytes > boundsCapacity_) {
        boundsCapacity_ = bytes;
        bounds_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, boundsCapacity_, nullptr, GL_DYNAMIC_READ);
      }
      glBindBuffer(GL_SHADER_STORAGE_BUFFER, bounds_.id());
      glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0, bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SPLAT_BOUNDS, bounds_.id());
      glUniform1i(uniform(p, "measureBounds"), 1);
      glEnable(GL_RASTERIZER_DISCARD);
      glDrawArrays(GL_POINTS, first, n);
      glDisable(GL_RASTERIZER_DISCARD);
      glUniform1i(uniform(p, "measureBounds"), 0);
      glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
      levelBounds.resize(size_t(end));
      glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, bytes, levelBounds.data() + first);
      glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    };
    GLint count = 0;
    uint64_t cost = 0;  // of the samples counted: their bounds and their vertex work
    for (bool full = false; at.first + count < total && !full;) {
      if (at.first + count >= GLint(levelBounds.size())) {
        uint64_t left = budget->left() > cost ? budget->left() - cost : 0;
        GLint slice = GLint(std::clamp<uint64_t>(left / (4 * SplatBudget::kSampleCost), SplatBudget::kMinSlice,
                                                 SplatBudget::kBoundsSlice));
        if (left < uint64_t(SplatBudget::kMinSlice) * SplatBudget::kSampleCost && (budget->drewAny || count > 0))
          break;
        measure(at.first + count, slice);
      }
      for (; at.first + count < GLint(levelBounds.size()); ++count) {
        uint64_t c = uint64_t(levelBounds[size_t(at.first + count)]) + SplatBudget::kSampleCost;
        if (cost + c > budget->left()) {
          full = true;
          break;
        }
        cost += c;
      }
    }
    if (count == 0 && at.first < total && !budget->drewAny) {  // always advance
      if (at.first >= GLint(levelBounds.size())) measure(at.first, SplatBudget::kMinSlice);
      cost = levelBounds[size_t(at.first + count++)] + SplatBudget::kSampleCost;
    }
    if (count > 0) {
      profiler.begin(SS_STAGE_SPLATTING, k);
      glDrawArrays(GL_POINTS, at.first, count);
      profiler.end();
      budget->spent += cost;
      budget->drewAny = true;
      at.first += count;
    }
    if (at.first < total) done = false;  // the budget is spent: the next render goes on from here
    if (done) at.first = 0;
    else break;
  }
  glDisable(GL_BLEND);
  SplatDepth::endTest();
  if (debug_) {  // the selection pass: the view's selected samples, drawn as points
    profiler.begin(SS_STAGE_SPLATTING);
    GLuint d = selectionProgram_.id();
    glUseProgram(d);
    GLint unused[9];
    setSelectionUniforms(d, scene, view, irradiance, splatting, selection, unused);
    glBindFramebuffer(GL_FRAMEBUFFER, selectionFramebuffer_.id());
    glViewport(0, 0, width_, height_);
    samples_.draw();
    profiler.end();
  }
  glBindVertexArray(0);
  return done;
}

}  // namespace subsplat
