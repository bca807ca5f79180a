#include "pipeline/irradiance_buffer.h"

#include <algorithm>

#include "material/splat_kernel.h"

namespace subsplat {

void IrradianceBuffer::resize(int resolution, int levels, bool profileSplits) {
  if (resolution == resolution_ && levels == levels_ && profileSplits == profileSplits_) return;
  // Old storage goes first (less memory at the peak), and a failed allocation leaves a buffer
  // that the next call allocates again instead of one with mixed sizes.
  resolution_ = levels_ = 0;
  framebuffer_ = gl::Framebuffer();
  exitFramebuffer_ = gl::Framebuffer();
  for (gl::Texture* t : {&positionMaterial_, &fluxFootprint_, &normalObject_, &lightDepth_, &depthRange_, &depth_,
                         &profileSplit_, &exitDepth_, &exitZ_})
    t->reset();
  positionMaterial_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  fluxFootprint_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  normalObject_ = gl::makeTexture2D(GL_RGBA32F, resolution, resolution, GL_NEAREST, levels);
  lightDepth_ = gl::makeTexture2D(GL_RG32F, resolution, resolution);
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

void IrradianceBuffer::applyIncidence(const Scene& scene, const GpuScene& gpu, const LightView& view,
                                      GLuint transportTables, bool translucentOnly) {
  if (!exitProgram_) {
    exitProgram_ = gl::makeProgram("mesh.vert", "", "exit_depth.frag");
    incidenceProgram_ = gl::makeComputeProgram("incidence.comp");
  }
  if (!exitFramebuffer_) {  // made on first use: scenes without TABULATED materials never pay for it
    exitDepth_ = gl::makeTexture2D(GL_RGBA32F, resolution_, resolution_);
    exitZ_ = gl::makeTexture2D(GL_DEPTH_COMPONENT32F, resolution_, resolution_);
    exitFramebuffer_ = gl::makeFramebuffer({exitDepth_.id()}, exitZ_.id());
  }
  // Where the light leaves: the nearest surface facing away from it.
  GLuint e = exitProgram_.id();
  beginMeshPass(exitFramebuffer_.id(), resolution_, resolution_, {glm::vec4(1e30f, -2.0f, 0.0f, 0.0f)}, e);
  setLightUniforms(e, view);
  glUniform1i(uniform(e, "translucentOnly"), translucentOnly ? 1 : 0);
  drawMeshes(scene, gpu, e, view.viewProj);
  glDisable(GL_DEPTH_TEST);
  // The incidence factor on level 0.
  GLuint p = incidenceProgram_.id();
  glUseProgram(p);
  setLightUniforms(p, view);
  setTransportUniforms(p, transportTables);
  glUniform1i(uniform(p, "resolution"), resolution_);
  bindTexture(gl::UNIT_IRRADIANCE_POSITION_MATERIAL, GL_TEXTURE_2D, positionMaterial_.id());
  bindTexture(gl::UNIT_IRRADIANCE_NORMAL_OBJECT, GL_TEXTURE_2D, normalObject_.id());
  bindTexture(gl::UNIT_IRRADIANCE_LIGHT_DEPTH, GL_TEXTURE_2D, lightDepth_.id());
  bindTexture(gl::UNIT_IRRADIANCE_EXIT_DEPTH, GL_TEXTURE_2D, exitDepth_.id());
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  glBindImageTexture(gl::IMAGE_FLUX_FOOTPRINT, fluxFootprint_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glDispatchCompute(GLuint((resolution_ + 7) / 8), GLuint((resolution_ + 7) / 8), 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  gl::checkErrors("incidence factor");
}

namespace {

// What irradiance_buffer.frag and entry_points.frag both read: the light view, the buffer's
// resolution and the soft shadows on the light entering.
void setViewUniforms(GLuint p, const LightView& view, int resolution, const SoftEntries& soft) {
  setLightUniforms(p, view);
  glUniform1i(uniform(p, "resolution"), resolution);
  glUniform1i(uniform(p, "softEntries"), soft.on() ? 1 : 0);  // (entry_points.frag; irradiance_buffer.frag's variant)
  if (soft.on()) {
    setSoftShadowUniforms(p, view);
    glUniform1i(uniform(p, "softMapResolution"), soft.resolution);
    bindTexture(gl::UNIT_SHADOW_DEPTH, GL_TEXTURE_2D, soft.map);
  }
}

}  // namespace

void IrradianceBuffer::renderEntries(const Scene& scene, const GpuScene& gpu, const LightView& view,
                                     const SoftEntries& soft) {
  if (!entryProgram_) entryProgram_ = gl::makeProgram("mesh.vert", "", "entry_points.frag");
  const glm::vec4 empty(0, 0, 0, -2), far(1e30f, 0, 0, 0);
  GLuint p = entryProgram_.id();
  beginMeshPass(framebuffer_.id(), resolution_, resolution_, {empty, glm::vec4(0.0f), empty, far}, p);
  setViewUniforms(p, view, resolution_, soft);
  drawMeshes(scene, gpu, p, view.viewProj);
  glDisable(GL_DEPTH_TEST);
}

void IrradianceBuffer::render(const Scene& scene, const GpuScene& gpu, const LightView& view, const SoftEntries& soft) {
  const glm::vec4 empty(0, 0, 0, -2), zero(0.0f), far(1e30f, 0, 0, 0);
  GLuint p = programs_.get({{"TEXTURES", scene.textured()},
                            {"PROFILE_MAPS", scene.heterogeneous()},
                            {"SOFT_ENTRIES", soft.on()},
                            {"AREA_LIGHT", view.light->type == SS_LIGHT_AREA}});
  if (profileSplits_)
    beginMeshPass(framebuffer_.id(), resolution_, resolution_, {empty, zero, empty, far, zero}, p);
  else
    beginMeshPass(framebuffer_.id(), resolution_, resolution_, {empty, zero, empty, far}, p);
  setViewUniforms(p, view, resolution_, soft);
  glUniform1f(uniform(p, "orthoTexelArea"), view.orthoTexelArea);
  glUniform1f(uniform(p, "tanHalfFov"), view.tanHalfFov);
  glUniform1f(uniform(p, "footprintSigma"), float(SplatKernel::kFootprintSigma));
  glUniform1i(uniform(p, "profileSplits"), profileSplits_ ? 1 : 0);
  drawMeshes(scene, gpu, p, view.viewProj);
  glDisable(GL_DEPTH_TEST);
}

}  // namespace subsplat
