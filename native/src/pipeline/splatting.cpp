#include "pipeline/splatting.h"

#include <glm/gtc/type_ptr.hpp>

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

void Splatting::setSelectionUniforms(GLuint p, const Scene& scene, const LightView& view,
                                     const IrradianceBuffer& irradiance, const SplattingBuffer& splatting,
                                     const Selection& selection, GLint offsets[9]) {
  int res = irradiance.resolution();
  glUniform1i(uniform(p, "resolution"), res);
  setLightUniforms(p, view);
  int levels = selection.levels;
  for (int k = 0; k < 9; ++k) offsets[k] = 0;
  for (int k = 0; k < levels; ++k) {
    int size = std::max(res >> k, 1);
    offsets[k + 1] = offsets[k] + size * size;
  }
  for (int k = levels + 1; k < 9; ++k) offsets[k] = offsets[levels];
  glUniform1i(uniform(p, "levels"), levels);
  glUniform1iv(uniform(p, "levelOffset"), 9, offsets);
  glUniform1f(uniform(p, "z0"), selection.z0);
  glUniform1f(uniform(p, "alpha"), selection.alpha);
  glUniform1f(uniform(p, "shadowTexelSize"), view.shadowTexelSize);
  glUniformMatrix4fv(uniform(p, "worldToView"), 1, GL_FALSE, scene.camera().world_to_view);
  glUniformMatrix4fv(uniform(p, "viewToClip"), 1, GL_FALSE, scene.camera().view_to_clip);
  bindTexture(gl::UNIT_IRRADIANCE_POSITION_MATERIAL, GL_TEXTURE_2D, irradiance.positionMaterial());
  bindTexture(gl::UNIT_IRRADIANCE_FLUX_FOOTPRINT, GL_TEXTURE_2D, irradiance.fluxFootprint());
  bindTexture(gl::UNIT_IRRADIANCE_NORMAL_OBJECT, GL_TEXTURE_2D, irradiance.normalObject());
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_IRRADIANCE_DEPTH_RANGE, GL_TEXTURE_2D, irradiance.depthRange());
  glUniform1i(uniform(p, "profileSplits"), irradiance.profileSplits() ? 1 : 0);
  if (irradiance.profileSplits()) bindTexture(gl::UNIT_IRRADIANCE_PROFILE_SPLIT, GL_TEXTURE_2D, irradiance.profileSplit());
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

void Splatting::accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                           StageProfiler& profiler) {
  int levels = int(exitance_.size());
  for (size_t k = 0; k < levelCopies_.size(); ++k)  // each level as splatted, for the debug pass
    glCopyImageSubData(exitance_[k].id(), GL_TEXTURE_2D, 0, 0, 0, 0, levelCopies_[k].id(), GL_TEXTURE_2D, 0, 0, 0,
                       0, std::max(width_ >> int(k), 1), std::max(height_ >> int(k), 1), 1);
  if (levels <= 1) return;
  profiler.begin(SS_STAGE_SPLATTING, StageProfiler::kAccumulation);
  if (!accumulateProgram_) accumulateProgram_ = gl::makeProgram("fullscreen.vert", "", "accumulate.frag");
  GLuint p = accumulateProgram_.id();
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glUniform1f(uniform(p, "lambdaZ"), weights.lambdaZ);
  glUniform1f(uniform(p, "lambdaM"), weights.lambdaM);
  glUniform1f(uniform(p, "boundingDiameter"), std::max(weights.boundingDiameter, 1e-12f));
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  glBindVertexArray(empty_.id());
  for (int k = levels - 2; k >= 0; --k) {  // coarse to fine: level k += upsampled level k + 1
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[size_t(k)].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    bindTexture(gl::UNIT_COARSE_EXITANCE, GL_TEXTURE_2D, exitance_[size_t(k + 1)].id());
    glUniform1i(uniform(p, "fineLevel"), k);
    glUniform2i(uniform(p, "coarseSize"), std::max(width_ >> (k + 1), 1), std::max(height_ >> (k + 1), 1));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  profiler.end();
  gl::checkErrors("splat accumulation");
}

void Shading::resize(int width, int height) {
  if (!directProgram_) {
    directProgram_ = gl::makeProgram("fullscreen.vert", "", "direct_lighting.frag");
    finalProgram_ = gl::makeProgram("fullscreen.vert", "", "final_shading.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_) return;
  width_ = height_ = 0;  // as in IrradianceBuffer::resize
  directFramebuffer_.reset();
  resultFramebuffer_.reset();
  direct_.reset();
  result_.reset();
  direct_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  result_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  directFramebuffer_ = gl::makeFramebuffer({direct_.id()}, 0);
  resultFramebuffer_ = gl::makeFramebuffer({result_.id()}, 0);
  width_ = width;
  height_ = height;
}

void Shading::clear() {
  glBindFramebuffer(GL_FRAMEBUFFER, directFramebuffer_.id());
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
}

void Shading::directLighting(const Scene& scene, const LightView& view,
                             const IrradianceBuffer& irradiance, const SplattingBuffer& splatting) {
  glBindFramebuffer(GL_FRAMEBUFFER, directFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  GLuint p = directProgram_.id();
  glUseProgram(p);
  setLightUniforms(p, view);
  setCameraUniforms(p, scene.camera());
  glUniform1i(uniform(p, "resolution"), irradiance.resolution());
  glUniform1f(uniform(p, "shadowTexelSize"), view.shadowTexelSize);
  glUniform1i(uniform(p, "unshadowedOutside"), view.unshadowedOutside ? 1 : 0);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_IRRADIANCE_LIGHT_DEPTH, GL_TEXTURE_2D, irradiance.lightDepth());
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

void Shading::finalShading(const Scene& scene, const SplattingBuffer& splatting, GLuint exitance,
                           const float background[4]) {
  glBindFramebuffer(GL_FRAMEBUFFER, resultFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  GLuint p = finalProgram_.id();
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glUniform4fv(uniform(p, "background"), 1, background);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_EXITANCE_BUFFER, GL_TEXTURE_2D, exitance);
  bindTexture(gl::UNIT_DIRECT_RADIANCE, GL_TEXTURE_2D, direct_.id());
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace subsplat
