#include "pipeline/shading.h"

#include <glm/gtc/type_ptr.hpp>

#include <string>

namespace subsplat {

void Shading::resize(int width, int height) {
  if (!throughProgram_) {
    throughProgram_ = gl::makeProgram("fullscreen.vert", "", "direct_through.frag");
    empty_ = gl::makeVertexArray();
  }
  if (width == width_ && height == height_) return;
  width_ = height_ = 0;  // as in IrradianceBuffer::resize
  directFramebuffer_.reset();
  resultFramebuffer_.reset();
  direct_.reset();
  result_.reset();
  throughFramebuffers_.clear();
  throughDirectFramebuffer_.reset();
  through_.reset();
  throughDirect_.reset();
  throughViews_ = 0;
  readThroughDirect_ = false;
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
  readThroughDirect_ = false;
}

bool Shading::keepThrough(int views) {
  uint64_t bytes = uint64_t(width_) * uint64_t(height_) * 32u * uint64_t(views);
  if (views <= 0 || bytes > kKeptThroughBytes) return false;
  if (views != throughViews_) {
    // Only within the memory budget: keeping this light is a saving, not a need (without it an
    // edit draws the views again), so it never fails a render.
    uint64_t more = bytes + (throughDirect_ ? 0 : uint64_t(width_) * uint64_t(height_) * 16u);
    uint64_t held = gl::gpuBytes() - through_.bytes(), budget = gl::memoryBudget();
    if (held > budget || more > budget - held) return false;
    throughFramebuffers_.clear();
    through_.reset();
    throughViews_ = 0;  // until the layers are made
    gl::Purpose purpose("the light through thin parts kept for material edits (" + std::to_string(views) +
                        " light views)");
    through_ = gl::makeTexture2DArray(GL_RGBA32F, width_, height_, 2 * views);
    for (int v = 0; v < views; ++v)
      throughFramebuffers_.push_back(gl::makeFramebufferWithLayers(direct_.id(), through_.id(), 2 * v, 2));
    if (!throughDirect_) {
      throughDirect_ = gl::makeTexture2D(GL_RGBA32F, width_, height_);
      throughDirectFramebuffer_ = gl::makeFramebuffer({throughDirect_.id()}, 0);
    }
    throughViews_ = views;
  }
  const float zero[4] = {0, 0, 0, 0};
  for (const gl::Framebuffer& f : throughFramebuffers_) {
    glBindFramebuffer(GL_FRAMEBUFFER, f.id());
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearBufferfv(GL_COLOR, 2, zero);
  }
  return true;
}

void Shading::addKeptThrough(const SplattingBuffer& splatting, GLuint transportTables) {
  glBindFramebuffer(GL_FRAMEBUFFER, throughDirectFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_BLEND);
  GLuint p = throughProgram_.id();
  glUseProgram(p);
  glUniform1i(uniform(p, "views"), throughViews_);
  setTransportUniforms(p, transportTables);
  bindTexture(gl::UNIT_DIRECT_RADIANCE, GL_TEXTURE_2D, direct_.id());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_KEPT_THROUGH, GL_TEXTURE_2D_ARRAY, through_.id());
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  readThroughDirect_ = true;
}

void Shading::directLighting(const Scene& scene, const LightView& view, const ShadowInputs& shadow,
                             const SplattingBuffer& splatting, GLuint transportTables, int keptView) {
  bool kept = keptView >= 0 && keptView < throughViews_;
  glBindFramebuffer(GL_FRAMEBUFFER, kept ? throughFramebuffers_[size_t(keptView)].id() : directFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  int softShadows = view.softSize <= 0.0f ? 0 : view.light->type == SS_LIGHT_SUN ? 1 : 2;
  GLuint p = directPrograms_.get({{"SOFT_SHADOWS", softShadows},
                                  {"TRANSMISSION", scene.tabulated()},
                                  {"AREA_LIGHT", view.light->type == SS_LIGHT_AREA}});
  glUseProgram(p);
  setLightUniforms(p, view);
  setCameraUniforms(p, scene.camera());
  glUniform1i(uniform(p, "resolution"), shadow.resolution);
  glUniform1i(uniform(p, "unshadowedOutside"), view.unshadowedOutside ? 1 : 0);
  setSoftShadowUniforms(p, view);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_SPLATTING_ALBEDO, GL_TEXTURE_2D, splatting.albedo());
  bindTexture(gl::UNIT_SPLATTING_SHADING_NORMAL, GL_TEXTURE_2D, splatting.shadingNormal());
  bindTexture(gl::UNIT_IRRADIANCE_LIGHT_DEPTH, GL_TEXTURE_2D, shadow.lightDepth);
  bindTexture(gl::UNIT_SHADOW_DEPTH, GL_TEXTURE_2D, shadow.shadowDepth);
  bindTexture(gl::UNIT_SOFT_DEPTH, GL_TEXTURE_2D, shadow.softDepth ? shadow.softDepth : shadow.lightDepth);
  glUniform1i(uniform(p, "shadowResolution"), shadow.shadowResolution);
  glUniform1i(uniform(p, "keptThrough"), kept ? 1 : 0);
  if (scene.tabulated()) {
    bindTexture(gl::UNIT_IRRADIANCE_POSITION_MATERIAL, GL_TEXTURE_2D, shadow.positionMaterial);
    bindTexture(gl::UNIT_IRRADIANCE_NORMAL_OBJECT, GL_TEXTURE_2D, shadow.normalObject);
    setTransportUniforms(p, transportTables);
  }
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

void Shading::finalShading(const Scene& scene, const SplattingBuffer& splatting, GLuint exitance,
                           GLuint transportTables, const float background[4], const EnvironmentInputs& environment,
                           const RenderLights& world, float weight, bool first) {
  glBindFramebuffer(GL_FRAMEBUFFER, resultFramebuffer_.id());
  glViewport(0, 0, width_, height_);
  bool accumulate = weight != 1.0f;
  if (accumulate) {
    if (first) {
      const float zero[4] = {0, 0, 0, 0};
      glClearBufferfv(GL_COLOR, 0, zero);
    }
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_CONSTANT_ALPHA, GL_ONE);
    glBlendColor(0.0f, 0.0f, 0.0f, weight);
  }
  bool blackWorld = !world.worldHarmonics && world.worldRadiance == glm::vec3(0.0f) && world.worldBelow == glm::vec3(0.0f);
  GLuint p = finalPrograms_.get({{"ENVIRONMENT", environment.texture != 0},
                                 {"TRANSMISSION", scene.tabulated()},
                                 {"WORLD", world.worldHarmonics ? 2 : blackWorld ? 0 : 1}});
  glUseProgram(p);
  setCameraUniforms(p, scene.camera());
  glUniform4fv(uniform(p, "background"), 1, background);
  if (environment.texture != 0) {
    const SsCameraDesc& camera = scene.camera();
    glm::mat4 clipToWorld = glm::inverse(glm::make_mat4(camera.view_to_clip) * glm::make_mat4(camera.world_to_view));
    glUniformMatrix4fv(uniform(p, "clipToWorld"), 1, GL_FALSE, glm::value_ptr(clipToWorld));
    glUniform2f(uniform(p, "frameSize"), float(width_), float(height_));
    glUniformMatrix3fv(uniform(p, "environmentRotation"), 1, GL_FALSE, glm::value_ptr(environment.rotation));
    glUniform1f(uniform(p, "environmentStrength"), environment.strength);
    bindTexture(gl::UNIT_ENVIRONMENT, GL_TEXTURE_2D, environment.texture);
  }
  glUniform3fv(uniform(p, "worldAbove"), 1, &world.worldRadiance.x);
  glUniform3fv(uniform(p, "worldBelow"), 1, &world.worldBelow.x);
  glUniform3fv(uniform(p, "worldIrradiance"), 9, &world.worldIrradiance[0].x);
  glUniform1i(uniform(p, "worldUnshadowed"), world.unshadowed ? 1 : 0);
  bindTexture(gl::UNIT_SPLATTING_POSITION_OBJECT, GL_TEXTURE_2D, splatting.positionObject());
  bindTexture(gl::UNIT_SPLATTING_NORMAL_MATERIAL, GL_TEXTURE_2D, splatting.normalMaterial());
  bindTexture(gl::UNIT_SPLATTING_ALBEDO, GL_TEXTURE_2D, splatting.albedo());
  bindTexture(gl::UNIT_SPLATTING_SHADING_NORMAL, GL_TEXTURE_2D, splatting.shadingNormal());
  bindTexture(gl::UNIT_EXITANCE_BUFFER, GL_TEXTURE_2D, exitance);
  bindTexture(gl::UNIT_DIRECT_RADIANCE, GL_TEXTURE_2D, readThroughDirect_ ? throughDirect_.id() : direct_.id());
  setTransportUniforms(p, transportTables);
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

}  // namespace subsplat
