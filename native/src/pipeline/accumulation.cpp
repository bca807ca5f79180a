#include "pipeline/accumulation.h"

#include <algorithm>

#include "pipeline/splatting.h"

namespace subsplat {

void beginAccumulation(GLuint p, const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                       int transportLayers) {
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glUniform1f(uniform(p, "lambdaZ"), weights.lambdaZ);
  glUniform1f(uniform(p, "lambdaM"), weights.lambdaM);
  glUniform1f(uniform(p, "boundingDiameter"), std::max(weights.boundingDiameter, 1e-12f));
  glUniform1i(uniform(p, "transportLayers"), transportLayers);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
}

void Splatting::accumulate(const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                           StageProfiler& profiler, bool keepLevels) {
  int levels = int(exitance_.size());
  for (size_t k = 0; k < levelCopies_.size(); ++k)  // each level as splatted, for the debug pass
    glCopyImageSubData(exitance_[k].id(), GL_TEXTURE_2D, 0, 0, 0, 0, levelCopies_[k].id(), GL_TEXTURE_2D, 0, 0, 0,
                       0, std::max(width_ >> int(k), 1), std::max(height_ >> int(k), 1), 1);
  gathered_ = false;
  if (levels <= 1) return;
  profiler.begin(SS_STAGE_SPLATTING, StageProfiler::kAccumulation);
  // A budgeted render gathers copies: the levels stay as splatted, for its next chunks.
  std::vector<gl::Texture>& target = keepLevels ? gatheredLevels_ : exitance_;
  std::vector<gl::Framebuffer>& targetFramebuffers = keepLevels ? gatheredFramebuffers_ : framebuffers_;
  if (keepLevels) {
    if (gatheredLevels_.size() != size_t(levels)) {
      gatheredLevels_.clear();
      gatheredFramebuffers_.clear();
      for (int k = 0; k < levels; ++k) {
        gatheredLevels_.push_back(gl::makeTexture2D(GL_RGBA32F, std::max(width_ >> k, 1), std::max(height_ >> k, 1)));
        gatheredFramebuffers_.push_back(gl::makeFramebuffer({gatheredLevels_.back().id()}, 0));
      }
    }
    for (int k = 0; k < levels; ++k)
      glCopyImageSubData(exitance_[size_t(k)].id(), GL_TEXTURE_2D, 0, 0, 0, 0, gatheredLevels_[size_t(k)].id(),
                         GL_TEXTURE_2D, 0, 0, 0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1), 1);
    gathered_ = true;
  }
  if (!accumulateProgram_) accumulateProgram_ = gl::makeProgram("fullscreen.vert", "", "accumulate.frag");
  GLuint p = accumulateProgram_.id();
  beginAccumulation(p, scene, splatting, weights, 0);
  glBindVertexArray(empty_.id());
  for (int k = levels - 2; k >= 0; --k) {  // coarse to fine: level k += upsampled level k + 1
    glBindFramebuffer(GL_FRAMEBUFFER, targetFramebuffers[size_t(k)].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    bindTexture(gl::UNIT_COARSE_EXITANCE, GL_TEXTURE_2D, target[size_t(k + 1)].id());
    glUniform1i(uniform(p, "fineLevel"), k);
    glUniform2i(uniform(p, "coarseSize"), std::max(width_ >> (k + 1), 1), std::max(height_ >> (k + 1), 1));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  profiler.end();
  gl::checkErrors("splat accumulation");
}

}  // namespace subsplat
