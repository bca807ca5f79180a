#include "pipeline/splatting_buffer.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace subsplat {

void SplattingBuffer::resize(int width, int height, int levels) {
  if (width == width_ && height == height_ && levels == levels_) return;
  width_ = height_ = levels_ = 0;  // as in IrradianceBuffer::resize
  framebuffer_ = gl::Framebuffer();
  for (gl::Texture* t : {&positionObject_, &normalMaterial_, &albedo_, &shadingNormal_, &depth_}) t->reset();
  positionObject_ = gl::makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST, levels);
  normalMaterial_ = gl::makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST, levels);
  albedo_ = gl::makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST);
  shadingNormal_ = gl::makeTexture2D(GL_RGBA16F, width, height, GL_NEAREST);
  depth_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
  framebuffer_ = gl::makeFramebuffer({positionObject_.id(), normalMaterial_.id(), albedo_.id(), shadingNormal_.id()},
                                     depth_.id());
  width_ = width;
  height_ = height;
  levels_ = levels;
}

void SplattingBuffer::buildHierarchy(const SsCameraDesc& camera) {
  if (levels_ <= 1) return;
  if (!reduceProgram_) reduceProgram_ = gl::makeComputeProgram("splatting_reduce.comp");
  GLuint p = reduceProgram_.id();
  glUseProgram(p);
  setCameraUniforms(p, camera);
  for (int fine = 0; fine + 1 < levels_; ++fine) {
    int fw = std::max(width_ >> fine, 1), fh = std::max(height_ >> fine, 1);
    int cw = std::max(width_ >> (fine + 1), 1), ch = std::max(height_ >> (fine + 1), 1);
    bindTexture(gl::UNIT_FINE_POSITION_OBJECT, GL_TEXTURE_2D, positionObject_.id());
    bindTexture(gl::UNIT_FINE_NORMAL_MATERIAL, GL_TEXTURE_2D, normalMaterial_.id());
    glUniform1i(uniform(p, "fineLevel"), fine);
    glUniform2i(uniform(p, "fineSize"), fw, fh);
    glUniform2i(uniform(p, "coarseSize"), cw, ch);
    glBindImageTexture(gl::IMAGE_COARSE_POSITION_OBJECT, positionObject_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(gl::IMAGE_COARSE_NORMAL_MATERIAL, normalMaterial_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(GLuint((cw + 7) / 8), GLuint((ch + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  gl::checkErrors("splatting hierarchy");
}

void SplattingBuffer::render(const Scene& scene, const GpuScene& gpu) {
  const glm::vec4 none(0, 0, 0, -1);
  GLuint p = sceneVariant(programs_, scene);
  beginMeshPass(framebuffer_.id(), width_, height_, {none, none, glm::vec4(1.0f), glm::vec4(0.0f)}, p);
  setCameraUniforms(p, scene.camera());
  glm::mat4 viewProj = glm::make_mat4(scene.camera().view_to_clip) *
                       glm::make_mat4(scene.camera().world_to_view);
  drawMeshes(scene, gpu, p, viewProj);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace subsplat
