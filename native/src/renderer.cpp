#include "renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "pipeline/auto_quality.h"
#include "util/error.h"
#include "world_light.h"

namespace subsplat {

Renderer::Renderer() {
  if (epoxy_gl_version() < 43)
    fail(SS_GL_ERROR, "OpenGL 4.3 or newer is required, the current context has " +
                          std::to_string(epoxy_gl_version() / 10) + "." +
                          std::to_string(epoxy_gl_version() % 10));
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize_);
  scene_.setMeshObserver(&gpuScene_);
}

void Renderer::setSettings(const SsSettings& s) {
  require(s.method == SS_METHOD_BRUTE || s.method == SS_METHOD_MULTIRES || s.method == SS_METHOD_ADAPTIVE ||
              s.method == SS_METHOD_FULL || s.method == SS_METHOD_REFERENCE,
          "unknown method " + std::to_string(s.method));
  require(std::isfinite(s.epsilon) && s.epsilon >= 0.0f && s.epsilon <= 0.5f,
          "epsilon must be 0 (the default) or in (0, 0.5], got " + std::to_string(s.epsilon));
  require(std::isfinite(s.lambda_z) && s.lambda_z >= 0.0f && s.lambda_z <= 1e4f,
          "lambda_z must be 0 (the default) or in (0, 1e4], got " + std::to_string(s.lambda_z));
  require(std::isfinite(s.lambda_m) && s.lambda_m >= 0.0f && s.lambda_m <= 1e4f,
          "lambda_m must be 0 (the default) or in (0, 1e4], got " + std::to_string(s.lambda_m));
  require(s.levels >= 0 && s.levels <= 8, "levels must be 0 (automatic) or in [1, 8], got " +
                                              std::to_string(s.levels));
  require(std::isfinite(s.z0_factor) && s.z0_factor >= 0.0f && s.z0_factor <= 100.0f,
          "z0 factor must be 0 (the default) or in (0, 100], got " + std::to_string(s.z0_factor));
  require(std::isfinite(s.alpha) && s.alpha >= 0.0f && s.alpha <= 1e4f,
          "alpha must be 0 (the default) or in (0, 1e4], got " + std::to_string(s.alpha));
  require(s.reference_samples == 0 || (s.reference_samples >= 1000 && s.reference_samples <= 100000000),
          "reference samples must be 0 (the default) or in [1e3, 1e8], got " +
              std::to_string(s.reference_samples));
  require(s.irradiance_resolution == 0 || (s.irradiance_resolution >= 16 && s.irradiance_resolution <= 8192),
          "irradiance resolution must be 0 (automatic) or in [16, 8192], got " +
              std::to_string(s.irradiance_resolution));
  require(std::isfinite(s.target_error) && (s.target_error == 0.0f || (s.target_error >= 1e-3f && s.target_error <= 0.5f)),
          "target error must be 0 (the default) or in [0.001, 0.5], got " + std::to_string(s.target_error));
  if (s.irradiance_resolution > maxTextureSize_)
    fail(SS_LIMIT_EXCEEDED, "irradiance resolution " + std::to_string(s.irradiance_resolution) +
                                " exceeds this GPU's texture limit of " + std::to_string(maxTextureSize_));
  for (float c : s.background) require(std::isfinite(c), "background colour must be finite");
  settings_ = s;
  if (settings_.reference_samples == 0) settings_.reference_samples = kDefaultReferenceSamples;
  if (settings_.z0_factor == 0.0f) settings_.z0_factor = kDefaultZ0Factor;
  if (settings_.alpha == 0.0f) settings_.alpha = kDefaultAlpha;
  if (settings_.epsilon == 0.0f) settings_.epsilon = kDefaultEpsilon;
  if (settings_.lambda_z == 0.0f) settings_.lambda_z = kDefaultLambda;
  if (settings_.lambda_m == 0.0f) settings_.lambda_m = kDefaultLambda;
  if (settings_.target_error == 0.0f) settings_.target_error = kDefaultTargetError;
}

void Renderer::uploadMaterials() {
  scene_.resolveMaterials();
  gpuScene_.update(scene_);
  materialTables_.update(scene_, settings_.epsilon);
}

void Renderer::countCoverage(int width, int height, const float* rgba) {
  size_t pixels = size_t(width) * height;
  for (size_t i = 0; i < pixels; ++i) {
    const float* out = rgba + 4 * i;
    if (!std::isfinite(out[0]) || !std::isfinite(out[1]) || !std::isfinite(out[2]) || !std::isfinite(out[3]))
      ++stats_.nonfinite_pixels;
  }
  CoverageCounts counts = coverage_.count(splatting_, splats_.exitance(), int(scene_.denseMaterials().size()),
                                          width, height);
  stats_.translucent_pixels = counts.translucentPixels;
  stats_.lit_translucent_pixels = counts.litTranslucentPixels;
}

void Renderer::render(int width, int height, float* rgba) {
  auto start = std::chrono::steady_clock::now();
  require(rgba != nullptr, "output buffer is NULL");
  require(width > 0 && height > 0, "render size must be positive, got " + std::to_string(width) +
                                       " x " + std::to_string(height));
  if (width > maxTextureSize_ || height > maxTextureSize_)
    fail(SS_LIMIT_EXCEEDED, "render size " + std::to_string(width) + " x " + std::to_string(height) +
                                " exceeds this GPU's texture limit of " + std::to_string(maxTextureSize_));
  if (!scene_.hasCamera()) fail(SS_INVALID_ARGUMENT, "no camera was set");
  lastMethod_ = -1;
  if (settings_.method == SS_METHOD_REFERENCE) {
    renderReference(width, height, rgba);
    return;
  }
  gl::StateGuard guard;
  while (glGetError() != GL_NO_ERROR) {  // errors left by the host are not ours
  }
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearDepth(1.0);
  glDepthRange(0.0, 1.0);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);

  uploadMaterials();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_MATERIALS, materialTables_.materials());
  bool adaptive = settings_.method == SS_METHOD_ADAPTIVE || settings_.method == SS_METHOD_FULL;
  bool multires = settings_.method == SS_METHOD_MULTIRES || settings_.method == SS_METHOD_FULL;
  Bounds translucent = scene_.bounds(true), all = scene_.bounds(false);
  int resolution = settings_.irradiance_resolution > 0 ? settings_.irradiance_resolution : chooseResolution(scene_, translucent, settings_.target_error, maxTextureSize_);
  Levels chosen = chooseLevels(scene_, settings_, width, height, translucent, resolution, adaptive, multires);
  int levels = chosen.irradiance, splatLevels = chosen.splat;
  {
    std::string size = std::to_string(resolution);
    gl::Purpose purpose("the irradiance buffers (" + size + " x " + size + " texels, " + std::to_string(levels) +
                        " levels; lower the irradiance resolution" +
                        (settings_.irradiance_resolution == 0 ? " or raise the target error)" : ")"));
    irradiance_.resize(resolution, levels, scene_.heterogeneous());
  }
  {
    gl::Purpose purpose("the splatting buffers (" + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels, " + std::to_string(splatLevels) + " levels; lower the render resolution)");
    splatting_.resize(width, height, splatLevels);
    splats_.setDebug(settings_.debug_passes != 0);
    splats_.resize(width, height, splatLevels);
    shading_.resize(width, height);
  }
  gl::checkErrors("buffer allocation");

  stats_ = SsStats{};
  StageProfiler& profiler = profiler_;
  profiler.newFrame();
  profiler.begin(SS_STAGE_BUFFERS);
  splatting_.render(scene_, gpuScene_);
  splatting_.buildHierarchy(scene_.camera());
  profiler.end();
  splats_.clear();
  shading_.clear();
  gl::checkErrors("splatting buffer");

  Selection selection{levels, settings_.z0_factor * translucent.radius(), settings_.alpha};
  KernelTables kernels = materialTables_.kernels();
  stats_.levels = levels;
  stats_.splat_levels = splatLevels;
  stats_.irradiance_resolution = resolution;
  double coarsest = lightTexel(scene_, translucent, resolution, false);
  stats_.texels_per_range = coarsest > 0.0 ? float(shortestRange(scene_) / coarsest) : 0.0f;
  int res = irradiance_.resolution();
  RenderLights lights = renderLights(scene_);
  for (size_t i = 0; i < lights.lights.size(); ++i) {
    for (LightView view : lightViews(lights.lights[i], translucent, all, res)) {
      if (lights.world[i]) view.worldDirections = &lights.worldDirections;
      profiler.begin(SS_STAGE_BUFFERS);
      irradiance_.render(scene_, gpuScene_, view);
      if (scene_.tabulated()) irradiance_.applyIncidence(scene_, gpuScene_, view, kernels.transport);
      if (adaptive) irradiance_.buildHierarchy();
      profiler.end();
      if (!translucent.empty()) splats_.splat(scene_, view, irradiance_, splatting_, kernels, selection, profiler);
      profiler.begin(SS_STAGE_SHADING);
      shading_.directLighting(scene_, view, irradiance_, splatting_, kernels.transport);
      profiler.end();
      ++stats_.light_views;
      gl::checkErrors("light view");
    }
  }
  if (!translucent.empty()) {  // (one level: only keeps the debug copy)
    splats_.accumulate(scene_, splatting_, {settings_.lambda_z, settings_.lambda_m, 2.0f * translucent.radius()},
                       profiler);
    stats_.splat_count = splats_.readSelectionCounts(stats_.selected_per_level);
  }
  profiler.begin(SS_STAGE_SHADING);
  shading_.finalShading(scene_, splatting_, splats_.exitance(), kernels.transport, settings_.background,
                        lights.worldRadiance, lights.worldBelow, lights.unshadowed);
  profiler.end();

  profiler.begin(SS_STAGE_READBACK);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, shading_.resultFramebuffer());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba);
  profiler.end();
  gl::checkErrors("read-back");
  profiler.collect(stats_);
  countCoverage(width, height, rgba);
  stats_.width = width;
  stats_.height = height;
  stats_.frame_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  lastMethod_ = settings_.method, lastWidth_ = width, lastHeight_ = height;
}

void Renderer::renderReference(int width, int height, float* rgba) {
  scene_.resolveMaterials();
  ReferenceOptions options;
  options.samples = settings_.reference_samples;
  options.background = glm::make_vec4(settings_.background);
  SsStats stats{};
  reference_.render(scene_, options, width, height, rgba, progress_, stats);
  stats_ = stats;
  lastMethod_ = settings_.method, lastWidth_ = width, lastHeight_ = height;
}

void Renderer::readPass(int pass, int width, int height, float* rgba) {
  require(rgba != nullptr, "output buffer is NULL");
  require(pass >= SS_PASS_EXITANCE && pass < SS_PASS_LEVEL_EXITANCE + 8, "unknown pass " + std::to_string(pass));
  if (lastMethod_ < 0) fail(SS_INVALID_ARGUMENT, "there is no successful render to read a pass from");
  require(width == lastWidth_ && height == lastHeight_,
          "pass size " + std::to_string(width) + " x " + std::to_string(height) + " differs from the last render's " +
              std::to_string(lastWidth_) + " x " + std::to_string(lastHeight_));
  size_t pixels = size_t(width) * height;
  if (lastMethod_ == SS_METHOD_REFERENCE) {
    require(pass == SS_PASS_EXITANCE, "REFERENCE has only the exitance pass");
    std::copy(reference_.exitance().begin(), reference_.exitance().begin() + 4 * pixels, rgba);
    return;
  }
  gl::StateGuard guard;
  if (pass != SS_PASS_EXITANCE) {
    require(settings_.debug_passes != 0, "debug passes were not enabled for the last render (debug_passes)");
    int level = pass - SS_PASS_LEVEL_EXITANCE;
    require(pass == SS_PASS_SELECTION || level < splats_.levels(),
            "the last render had " + std::to_string(splats_.levels()) + " splatting levels, not " +
                std::to_string(level + 1));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    if (pass == SS_PASS_SELECTION) {
      glBindTexture(GL_TEXTURE_2D, splats_.selection());
      glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, rgba);
      gl::checkErrors("pass read-back");
      return;
    }
    int lw = std::max(width >> level, 1), lh = std::max(height >> level, 1);
    std::vector<float> small(size_t(lw) * lh * 4);
    glBindTexture(GL_TEXTURE_2D, splats_.levelExitance(level));
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, small.data());
    gl::checkErrors("pass read-back");
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* in = &small[(size_t(std::min(y >> level, lh - 1)) * lw + std::min(x >> level, lw - 1)) * 4];
        float* out = rgba + (size_t(y) * width + x) * 4;
        out[0] = in[0], out[1] = in[1], out[2] = in[2], out[3] = 1.0f;
      }
    return;
  }
  std::vector<float> normalMaterial(pixels * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindTexture(GL_TEXTURE_2D, splatting_.normalMaterial());
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, normalMaterial.data());
  glBindTexture(GL_TEXTURE_2D, splats_.exitance());
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, rgba);
  gl::checkErrors("pass read-back");
  const auto& materials = scene_.denseMaterials();
  for (size_t i = 0; i < pixels; ++i) {
    int m = int(normalMaterial[4 * i + 3]);
    bool translucent = m >= 0 && size_t(m) < materials.size() && materials[size_t(m)].kernel;
    float* e = rgba + 4 * i;
    if (!translucent) e[0] = e[1] = e[2] = 0.0f;
    e[3] = translucent ? 1.0f : 0.0f;
  }
}

}  // namespace subsplat
