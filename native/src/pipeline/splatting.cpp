#include "pipeline/splatting.h"

#include <algorithm>

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

void Splatting::splat(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                      const SplattingBuffer& splatting, const KernelTables& kernels, const Selection& selection,
                      StageProfiler& profiler) {
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
  for (int k = 0; k < splatLevels; ++k) {
    profiler.begin(SS_STAGE_SPLATTING, k);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    glUniform1i(uniform(p, "splatLevel"), k);
    glDrawArrays(GL_POINTS, 0, offsets[levels]);
    profiler.end();
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
}

}  // namespace subsplat
