#include "pipeline/accumulation.h"

#include <algorithm>

#include "pipeline/splatting.h"

namespace subsplat {

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

}  // namespace subsplat
