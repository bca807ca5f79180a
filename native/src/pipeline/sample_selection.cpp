#include "pipeline/sample_selection.h"

#include <algorithm>

namespace subsplat {

void SelectionCounts::clear() {
  if (!buffer_) buffer_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, 8 * sizeof(GLuint), nullptr, GL_DYNAMIC_READ);
  const GLuint zeros[8] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_.id());
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zeros, zeros);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void SelectionCounts::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SELECTION_COUNTS, buffer_.id());
}

uint64_t SelectionCounts::read(uint64_t selectedPerLevel[8]) {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  GLuint counts[8] = {};
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_.id());
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof counts, counts);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  uint64_t selected = 0;
  for (int k = 0; k < 8; ++k) {
    selectedPerLevel[k] += counts[k];
    selected += counts[k];
  }
  return selected;
}

void setSelectionUniforms(GLuint p, const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                          const SplattingBuffer& splatting, const Selection& selection, GLint offsets[9]) {
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

void SampleList::build(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                       const SplattingBuffer& splatting, const Selection& selection, SelectionCounts* counts) {
  if (!program_) program_ = gl::makeComputeProgram("select_samples.comp");
  GLuint p = program_.id();
  glUseProgram(p);
  GLint offsets[9];
  setSelectionUniforms(p, scene, view, irradiance, splatting, selection, offsets);
  size_t texels = size_t(offsets[selection.levels]);
  GLuint groups = GLuint((texels + kGroupSamples - 1) / kGroupSamples);
  if (texels > capacity_ || !list_) {
    gl::Purpose purpose("the splatted samples' list");
    capacity_ = std::max<size_t>(texels, 1);
    size_t blocks = (capacity_ + kGroupSamples - 1) / kGroupSamples;
    list_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, (4 + capacity_) * sizeof(GLuint), nullptr, GL_DYNAMIC_DRAW);
    ranks_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, blocks * kGroupInvocations * sizeof(GLuint), nullptr, GL_DYNAMIC_DRAW);
    blocks_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, blocks * sizeof(GLuint), nullptr, GL_DYNAMIC_DRAW);
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SAMPLE_LIST, list_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SAMPLE_RANKS, ranks_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SAMPLE_BLOCKS, blocks_.id());
  if (counts) counts->bind();
  glUniform1i(uniform(p, "countSelection"), counts ? 1 : 0);
  for (int pass = 0; pass < 3; ++pass) {
    glUniform1i(uniform(p, "pass"), pass);
    glDispatchCompute(pass == 1 ? 1u : std::max(groups, 1u), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  gl::checkErrors("sample selection");
}

void SampleList::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_SAMPLE_LIST, list_.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, list_.id());
}

void SampleList::draw() const { glDrawArraysIndirect(GL_POINTS, nullptr); }

GLint SampleList::count() const {
  GLuint n = 0;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, list_.id());
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof n, &n);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return GLint(n);
}

}  // namespace subsplat
