#include "pipeline/buffers.h"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

#include "material/splat_kernel.h"

namespace subsplat {

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

void bindTexture(int unit, GLenum target, GLuint texture) {
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(target, texture);
  glBindSampler(GLuint(unit), 0);  // the texture's own filtering and wrapping, not the host's sampler
}

void setLightUniforms(GLuint program, const LightView& view) {
  const SsLightDesc& l = *view.light;
  float scale = l.type == SS_LIGHT_SUN ? 1.0f : 1.0f / (4.0f * float(M_PI));  // W -> W/sr
  glm::vec3 radiant = glm::make_vec3(l.color) * (l.strength * scale);
  glm::vec3 direction = l.type == SS_LIGHT_POINT ? glm::vec3(0, 0, -1)
                                                 : glm::normalize(glm::make_vec3(l.direction));
  float cosHalf = std::cos(0.5f * l.spot_size);
  glUniformMatrix4fv(uniform(program, "lightViewProj"), 1, GL_FALSE, glm::value_ptr(view.viewProj));
  glUniform3fv(uniform(program, "lightPosition"), 1, l.position);
  glUniform3fv(uniform(program, "lightDirection"), 1, glm::value_ptr(direction));
  glUniform3fv(uniform(program, "lightRadiant"), 1, glm::value_ptr(radiant));
  glUniform1i(uniform(program, "lightType"), l.type);
  glUniform1f(uniform(program, "lightCosHalfSpot"), l.type == SS_LIGHT_SPOT ? cosHalf : -2.0f);
  glUniform1f(uniform(program, "lightSpotSmooth"), (1.0f - cosHalf) * l.spot_blend);
}

void drawMeshes(const Scene& scene, const GpuScene& gpu, GLuint program, const glm::mat4& viewProj) {
  glUniformMatrix4fv(uniform(program, "viewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
  bindTexture(gl::UNIT_PROFILE_MAPS, GL_TEXTURE_BUFFER, gpu.profileMaps());
  for (const auto& [id, mesh] : scene.meshes()) {
    glm::mat3 normalToWorld = glm::transpose(glm::inverse(glm::mat3(mesh.objectToWorld)));
    glUniformMatrix4fv(uniform(program, "objectToWorld"), 1, GL_FALSE,
                       glm::value_ptr(mesh.objectToWorld));
    glUniformMatrix3fv(uniform(program, "normalToWorld"), 1, GL_FALSE, glm::value_ptr(normalToWorld));
    glUniform1f(uniform(program, "objectIndex"), float(mesh.index));
    glUniform1i(uniform(program, "meshHasUvs"), mesh.hasUvs() ? 1 : 0);
    const GpuMesh& buffers = gpu.mesh(id);
    bindTexture(gl::UNIT_TRIANGLE_MATERIALS, GL_TEXTURE_BUFFER, buffers.triangleMaterials.id());
    glBindVertexArray(buffers.vertexArray.id());
    glDrawElements(GL_TRIANGLES, GLsizei(3 * mesh.triangleCount), GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
}

void IrradianceBuffer::resize(int resolution, int levels, bool profileSplits) {
  if (!program_) program_ = gl::makeProgram("mesh.vert", "", "irradiance_buffer.frag");
  if (resolution == resolution_ && levels == levels_ && profileSplits == profileSplits_) return;
  // Old storage goes first (less memory at the peak), and a failed allocation leaves a buffer
  // that the next call allocates again instead of one with mixed sizes.
  resolution_ = levels_ = 0;
  framebuffer_ = gl::Framebuffer();
  for (gl::Texture* t : {&positionMaterial_, &fluxFootprint_, &normalObject_, &lightDepth_, &depthRange_, &depth_,
                         &profileSplit_})
    t->reset();
  positionMaterial_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  fluxFootprint_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  normalObject_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  lightDepth_ = gl::makeTexture2D(GL_R32F, resolution, resolution);
  depthRange_ = gl::makeTexture2D(GL_RG32F, resolution, resolution, GL_NEAREST, levels);
  depth_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, resolution, resolution);
  if (profileSplits) {
    profileSplit_ = gl::makeTexture2D(GL_RGBA16F, resolution, resolution, GL_NEAREST, levels);
    framebuffer_ = gl::makeFramebuffer(
        {positionMaterial_.id(), fluxFootprint_.id(), normalObject_.id(), lightDepth_.id(), profileSplit_.id()},
        depth_.id());
  } else {
    profileSplit_ = gl::Texture();
    framebuffer_ = gl::makeFramebuffer(
        {positionMaterial_.id(), fluxFootprint_.id(), normalObject_.id(), lightDepth_.id()}, depth_.id());
  }
  resolution_ = resolution;
  levels_ = levels;
  profileSplits_ = profileSplits;
}

void IrradianceBuffer::buildHierarchy() {
  if (levels_ <= 1) return;
  if (!reduceProgram_) reduceProgram_ = gl::makeComputeProgram("irradiance_reduce.comp");
  GLuint p = reduceProgram_.id();
  glUseProgram(p);
  for (int fine = 0; fine + 1 < levels_; ++fine) {
    int size = std::max(resolution_ >> (fine + 1), 1);
    bindTexture(gl::UNIT_FINE_POSITION_MATERIAL, GL_TEXTURE_2D, positionMaterial_.id());
    bindTexture(gl::UNIT_FINE_FLUX_FOOTPRINT, GL_TEXTURE_2D, fluxFootprint_.id());
    bindTexture(gl::UNIT_FINE_NORMAL_OBJECT, GL_TEXTURE_2D, normalObject_.id());
    bindTexture(gl::UNIT_FINE_DEPTH_RANGE, GL_TEXTURE_2D, fine == 0 ? lightDepth_.id() : depthRange_.id());
    glUniform1i(uniform(p, "profileSplits"), profileSplits_ ? 1 : 0);
    if (profileSplits_) {
      bindTexture(gl::UNIT_FINE_PROFILE_SPLIT, GL_TEXTURE_2D, profileSplit_.id());
      glBindImageTexture(gl::IMAGE_COARSE_PROFILE_SPLIT, profileSplit_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    }
    glUniform1i(uniform(p, "fineLevel"), fine);
    glUniform2i(uniform(p, "coarseSize"), size, size);
    glBindImageTexture(gl::IMAGE_COARSE_POSITION_MATERIAL, positionMaterial_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(gl::IMAGE_COARSE_FLUX_FOOTPRINT, fluxFootprint_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(gl::IMAGE_COARSE_NORMAL_OBJECT, normalObject_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(gl::IMAGE_COARSE_DEPTH_RANGE, depthRange_.id(), fine + 1, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glDispatchCompute(GLuint((size + 7) / 8), GLuint((size + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  gl::checkErrors("irradiance hierarchy");
}

void IrradianceBuffer::render(const Scene& scene, const GpuScene& gpu, const LightView& view) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, resolution_, resolution_);
  const float empty[4] = {0, 0, 0, -2}, zero[4] = {0, 0, 0, 0}, far[4] = {1e30f, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, empty);
  glClearBufferfv(GL_COLOR, 1, zero);
  glClearBufferfv(GL_COLOR, 2, empty);
  glClearBufferfv(GL_COLOR, 3, far);
  if (profileSplits_) glClearBufferfv(GL_COLOR, 4, zero);
  glDepthMask(GL_TRUE);  // before the clear: a masked depth buffer is not cleared
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  GLuint p = program_.id();
  glUseProgram(p);
  setLightUniforms(p, view);
  glUniform1i(uniform(p, "resolution"), resolution_);
  glUniform1f(uniform(p, "orthoTexelArea"), view.orthoTexelArea);
  glUniform1f(uniform(p, "tanHalfFov"), view.tanHalfFov);
  glUniform1f(uniform(p, "footprintSigma"), float(SplatKernel::kFootprintSigma));
  glUniform1i(uniform(p, "profileSplits"), profileSplits_ ? 1 : 0);
  drawMeshes(scene, gpu, p, view.viewProj);
  glDisable(GL_DEPTH_TEST);
}

void setCameraUniforms(GLuint program, const SsCameraDesc& camera) {
  glm::vec3 position = cameraPosition(camera), forward = cameraForward(camera);
  glUniform3fv(uniform(program, "cameraPosition"), 1, glm::value_ptr(position));
  glUniform3fv(uniform(program, "cameraForward"), 1, glm::value_ptr(forward));
  glUniform1i(uniform(program, "orthographic"), camera.orthographic);
}

void SplattingBuffer::resize(int width, int height, int levels) {
  if (!program_) program_ = gl::makeProgram("mesh.vert", "", "splatting_buffer.frag");
  if (width == width_ && height == height_ && levels == levels_) return;
  width_ = height_ = levels_ = 0;  // as in IrradianceBuffer::resize
  framebuffer_ = gl::Framebuffer();
  for (gl::Texture* t : {&positionObject_, &normalMaterial_, &depth_}) t->reset();
  positionObject_ = gl::makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST, levels);
  normalMaterial_ = gl::makeTexture2D(GL_RGBA32F, width, height, GL_NEAREST, levels);
  depth_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
  framebuffer_ = gl::makeFramebuffer({positionObject_.id(), normalMaterial_.id()}, depth_.id());
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
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, width_, height_);
  const float none[4] = {0, 0, 0, -1};
  glClearBufferfv(GL_COLOR, 0, none);
  glClearBufferfv(GL_COLOR, 1, none);
  glDepthMask(GL_TRUE);  // before the clear: a masked depth buffer is not cleared
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  GLuint p = program_.id();
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glm::mat4 viewProj = glm::make_mat4(scene.camera().view_to_clip) *
                       glm::make_mat4(scene.camera().world_to_view);
  drawMeshes(scene, gpu, p, viewProj);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace subsplat
