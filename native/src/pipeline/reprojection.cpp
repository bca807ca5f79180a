#include "pipeline/reprojection.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

#include "util/error.h"

namespace subsplat {

bool ShadowCopies::keep(size_t index, const ShadowInputs& source, bool withSurface) {
  int r = source.resolution;
  // PRECOMPUTED's views of shadows alone may have no light depth of the irradiance's resolution.
  bool depth = source.lightDepth != 0;
  bool ownShadow = source.shadowDepth != source.lightDepth;
  int s = ownShadow ? source.shadowResolution : 0;
  // The soft shadows' map, when it is neither of the others (ShadowInputs::softDepth).
  bool ownSoft = source.softDepth != 0 && source.softDepth != source.lightDepth && source.softDepth != source.shadowDepth;
  size_t bytes = size_t(r) * size_t(r) * ((withSurface ? 32 : 0) + (depth ? 8 : 0) + (ownSoft ? 8 : 0)) +
                 size_t(s) * size_t(s) * 8;
  if ((index + 1) * bytes > kBudgetBytes) return false;
  if (copies_.size() <= index) copies_.resize(index + 1);
  Copy& copy = copies_[index];
  if (copy.resolution != r || copy.withSurface != withSurface || copy.shadowResolution != s || copy.ownSoft != ownSoft ||
      bool(copy.depth) != depth) {
    copy = Copy{};
    try {
      gl::Purpose purpose("a copy of a shadow map for the anti-aliasing samples");
      if (depth) copy.depth = gl::makeTexture2D(GL_RG32F, r, r);
      if (withSurface) {
        copy.position = gl::makeTexture2D(GL_RGBA32F, r, r);
        copy.normal = gl::makeTexture2D(GL_RGBA32F, r, r);
      }
      if (ownShadow) copy.shadow = gl::makeTexture2D(GL_RG32F, s, s);
      if (ownSoft) copy.soft = gl::makeTexture2D(GL_RG32F, r, r);
    } catch (const Error& e) {
      if (e.status() != SS_LIMIT_EXCEEDED) throw;
      copy = Copy{};  // past the memory budget: this view's shadow map is drawn again per sample
      return false;
    }
    copy.resolution = r;
    copy.shadowResolution = s;
    copy.withSurface = withSurface;
    copy.ownSoft = ownSoft;
  }
  auto duplicate = [](GLuint from, GLuint to, int size) {
    glCopyImageSubData(from, GL_TEXTURE_2D, 0, 0, 0, 0, to, GL_TEXTURE_2D, 0, 0, 0, 0, size, size, 1);
  };
  if (depth) duplicate(source.lightDepth, copy.depth.id(), r);
  if (withSurface) {
    duplicate(source.positionMaterial, copy.position.id(), r);
    duplicate(source.normalObject, copy.normal.id(), r);
  }
  if (ownShadow) duplicate(source.shadowDepth, copy.shadow.id(), s);
  if (ownSoft) duplicate(source.softDepth, copy.soft.id(), r);
  GLuint soft = 0;
  if (ownSoft) soft = copy.soft.id();
  else if (source.softDepth != 0 && source.softDepth == source.shadowDepth && ownShadow) soft = copy.shadow.id();
  if (kept_.size() <= index) kept_.resize(index + 1);
  kept_[index] = {copy.depth.id(), copy.position.id(), copy.normal.id(), r,
                  ownShadow ? copy.shadow.id() : copy.depth.id(), ownShadow ? s : r, soft};
  return true;
}

const ShadowInputs* ShadowCopies::find(size_t index) const {
  return index < kept_.size() && kept_[index].resolution > 0 ? &kept_[index] : nullptr;
}

void ExitanceReprojection::resize(int width, int height) {
  if (!program_) {
    program_ = gl::makeProgram("fullscreen.vert", "", "reproject_exitance.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_) return;
  width_ = height_ = 0;  // as in IrradianceBuffer::resize
  framebuffer_.reset();
  exitance_.reset();
  exitance_ = gl::makeTexture2D(GL_RGBA32F, width, height);
  framebuffer_ = gl::makeFramebuffer({exitance_.id()}, 0);
  width_ = width;
  height_ = height;
}

void ExitanceReprojection::reproject(const SsCameraDesc& first, const SplattingBuffer& firstBuffer,
                                     GLuint firstExitance, const SsCameraDesc& camera, const SplattingBuffer& sample) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  GLuint p = program_.id();
  glUseProgram(p);
  glm::mat4 viewProj = glm::make_mat4(first.view_to_clip) * glm::make_mat4(first.world_to_view);
  glUniformMatrix4fv(uniform(p, "firstViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
  setCameraUniforms(p, camera);
  // A pixel's height in view space at distance 1 (perspective) or in all (orthographic): 2 / (h P11).
  float p11 = std::abs(camera.view_to_clip[5]);
  glUniform1f(uniform(p, "pixelSpread"), p11 > 0.0f ? 2.0f / (float(height_) * p11) : 0.0f);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, sample.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, sample.normalMaterial());
  bindTexture(gl::UNIT_FIRST_SAMPLE_POSITION_OBJECT, GL_TEXTURE_2D, firstBuffer.positionObject());
  bindTexture(gl::UNIT_EXITANCE_BUFFER, GL_TEXTURE_2D, firstExitance);
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace subsplat
