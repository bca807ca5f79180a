#include "pipeline/splat_depth.h"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include "pipeline/pass_helpers.h"

namespace subsplat {

void SplatDepth::resize(int width, int height, int levels) {
  if (!program_) {
    program_ = gl::makeProgram("fullscreen.vert", "", "splat_depth.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_ && size_t(levels) == textures_.size()) return;
  width_ = height_ = 0;
  textures_.clear();
  framebuffers_.clear();
  for (int k = 0; k < levels; ++k) {
    textures_.push_back(gl::makeTexture2D(GL_DEPTH_COMPONENT32F, std::max(width >> k, 1), std::max(height >> k, 1)));
    framebuffers_.push_back(gl::makeFramebuffer({}, textures_.back().id()));
  }
  width_ = width;
  height_ = height;
}

void SplatDepth::clear() {
  const float zero = 0.0f;
  glDepthMask(GL_TRUE);
  for (const gl::Framebuffer& f : framebuffers_) {
    glBindFramebuffer(GL_FRAMEBUFFER, f.id());
    glClearBufferfv(GL_DEPTH, 0, &zero);
  }
  glDepthMask(GL_FALSE);
}

void SplatDepth::prepare(const Scene& scene, const SplattingBuffer& splatting) {
  // Beyond every surface: the far side of the scene's bounding sphere, and a little more.
  Bounds all = scene.bounds(false);
  glm::vec3 centre = glm::vec3(glm::make_mat4(scene.camera().world_to_view) * glm::vec4(all.center(), 1.0f));
  far_ = all.empty() ? 1.0f : std::max((glm::length(centre) + all.radius()) * 1.01f, 1e-6f);
  GLuint p = program_.id();
  glUseProgram(p);
  glUniformMatrix4fv(uniform(p, "worldToView"), 1, GL_FALSE, scene.camera().world_to_view);
  glUniform1f(uniform(p, "depthFar"), far_);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glBindVertexArray(empty_.id());
  for (size_t k = 0; k < framebuffers_.size(); ++k) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[k].id());
    glViewport(0, 0, std::max(width_ >> k, 1), std::max(height_ >> k, 1));
    glUniform1i(uniform(p, "splatLevel"), int(k));
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glDepthMask(GL_FALSE);
  glDisable(GL_DEPTH_TEST);
  gl::checkErrors("splatting depth");
}

void SplatDepth::beginTest() {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
}

void SplatDepth::endTest() { glDisable(GL_DEPTH_TEST); }

}  // namespace subsplat
