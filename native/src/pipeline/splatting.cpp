#include "pipeline/splatting.h"

#include <algorithm>
#include <cmath>

#include "material/splat_kernel.h"

namespace subsplat {

void Splatting::resize(int width, int height, int levels) {
  if (!program_) {
    program_ = gl::makeProgram("splat.vert", "splat.geom", "splat.frag");
    empty_ = gl::makeVertexArray();
  }
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
  for (int k = 0; k < levels; ++k) {
    exitance_.push_back(gl::makeTexture2D(GL_RGBA32F, std::max(width >> k, 1), std::max(height >> k, 1)));
    framebuffers_.push_back(gl::makeFramebuffer({exitance_.back().id()}, 0));
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
  if (selectionFramebuffer_) {
    glBindFramebuffer(GL_FRAMEBUFFER, selectionFramebuffer_.id());
    glClearBufferfv(GL_COLOR, 0, zero);
  }
  if (!counts_) counts_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, 8 * sizeof(GLuint), nullptr, GL_DYNAMIC_READ);
  const GLuint zeros[8] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_.id());
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zeros, zeros);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

uint64_t Splatting::readSelectionCounts(uint64_t selectedPerLevel[8]) {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint counts[8] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_.id());
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counts, counts);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  uint64_t selected = 0;
  for (int k = 0; k < 8; ++k) {
    selectedPerLevel[k] += counts[k];
    selected += counts[k];
  }
  return selected;
}

bool Splatting::splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                      const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
                      StageProfiler& profiler, SplatCursor* cursor, SplatBudget* budget) {
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  GLuint p = program_.id();
  glUseProgram(p);
  GLint offsets[9];
  setSelectionUniforms(p, scene, view, irradiance, splatting, selection, offsets);
  int levels = selection.levels;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SELECTION_COUNTS, counts_.id());  // zeroed by clear(), summed over views
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
  glUniform1i(uniform(p, "pairProfiles"), scene.heterogeneous() ? 1 : 0);
  glBindVertexArray(empty_.id());
  lastSampleCount_ = offsets[levels];
  if (budget) budget->lastChunk = 0, budget->viewMeasured = false;  // each view probes its own splats
  SplatCursor whole;
  SplatCursor& at = cursor ? *cursor : whole;
  bool done = true;
  for (; at.level < splatLevels && done; ++at.level) {
    int k = at.level;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    glUniform1i(uniform(p, "splatLevel"), k);
    GLint total = offsets[levels];
    if (!budget) {
      profiler.begin(SS_STAGE_SPLATTING, k);
      glDrawArrays(GL_POINTS, 0, total);
      profiler.end();
      continue;
    }
    while (at.first < total) {
      // Until a chunk has drawn a fragment, chunks grow to at most kProbe samples.
      GLint growth = std::max(2 * budget->lastChunk, 1);
      if (!budget->viewMeasured) growth = std::min(growth, SplatBudget::kProbe);
      GLint count = std::min(total - at.first, growth);
      if (budget->density > 0.0)
        count = GLint(std::min<double>(count, std::floor(double(budget->left()) / (2.0 * budget->density))));
      if (count < 1) {
        if (budget->drewAny) {
          done = false;  // the budget is spent: the next render goes on from here
          break;
        }
        count = 1;
      }
      profiler.begin(SS_STAGE_SPLATTING, k);
      glDrawArrays(GL_POINTS, at.first, count);
      uint64_t fragments = profiler.endCounted();
      budget->spent += fragments;
      budget->density = std::max(budget->density, double(fragments) / double(count));
      budget->drewAny = true;
      budget->lastChunk = count;
      if (fragments > 0) budget->viewMeasured = true;
      at.first += count;
    }
    if (done) at.first = 0;
    else break;
  }
  glDisable(GL_BLEND);
  if (debug_) {  // the selection pass: splat.vert's selection, drawn as points
    profiler.begin(SS_STAGE_SPLATTING);
    GLuint d = selectionProgram_.id();
    glUseProgram(d);
    GLint unused[9];
    setSelectionUniforms(d, scene, view, irradiance, splatting, selection, unused);
    glUniform1i(uniform(d, "splatLevel"), -1);  // not counted again
    glBindFramebuffer(GL_FRAMEBUFFER, selectionFramebuffer_.id());
    glViewport(0, 0, width_, height_);
    glDrawArrays(GL_POINTS, 0, offsets[levels]);
    profiler.end();
  }
  glBindVertexArray(0);
  return done;
}

}  // namespace subsplat
