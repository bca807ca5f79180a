#include "pipeline/coverage.h"

namespace subsplat {

CoverageCounts Coverage::count(const SplattingBuffer& splatting, GLuint exitance, int materialCount, int width,
                               int height) {
  if (!program_) program_ = gl::makeComputeProgram("coverage.comp");
  if (!counts_) counts_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, 2 * sizeof(GLuint), nullptr, GL_DYNAMIC_READ);
  const GLuint zeros[2] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_.id());
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zeros, zeros);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  GLuint p = program_.id();
  glUseProgram(p);
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_EXITANCE_BUFFER, GL_TEXTURE_2D, exitance);
  glUniform2i(uniform(p, "size"), width, height);
  glUniform1i(uniform(p, "materialCount"), materialCount);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_COVERAGE_COUNTS, counts_.id());
  glDispatchCompute(GLuint((width + 7) / 8), GLuint((height + 7) / 8), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint counts[2] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_.id());
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counts, counts);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  gl::checkErrors("coverage");
  return {counts[0], counts[1]};
}

}  // namespace subsplat
