#include "renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "pipeline/auto_quality.h"
#include "util/error.h"
#include "util/pixel_filter.h"
#include "world_light.h"

namespace subsplat {

namespace {
// Puts the host's camera back however a frame ends (the samples jitter it).
struct CameraRestore {
  Scene& scene;
  SsCameraDesc camera;
  ~CameraRestore() {
    try {
      scene.setCamera(camera);
    } catch (...) {  // it was accepted before: cannot fail
    }
  }
};
}  // namespace

Renderer::Renderer() {
  if (epoxy_gl_version() < 43)
    fail(SS_GL_ERROR, "OpenGL 4.3 or newer is required, the current context has " +
                          std::to_string(epoxy_gl_version() / 10) + "." +
                          std::to_string(epoxy_gl_version() % 10));
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize_);
  scene_.setMeshObserver(&gpuScene_);
}

void Renderer::setCamera(const SsCameraDesc& camera) {
  if (!scene_.hasCamera() || std::memcmp(&camera, &scene_.camera(), sizeof camera) != 0) scene().setCamera(camera);
}

void Renderer::setSettings(const SsSettings& s) {
  resume_.valid = false;
  require(s.method == SS_METHOD_BRUTE || s.method == SS_METHOD_MULTIRES || s.method == SS_METHOD_ADAPTIVE ||
              s.method == SS_METHOD_FULL || s.method == SS_METHOD_REFERENCE || s.method == SS_METHOD_MATERIAL_EDIT ||
              s.method == SS_METHOD_PRECOMPUTED,
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
  require(s.samples >= 0 && s.samples <= kMaxSamples,
          "samples must be 0 (one) or in [1, " + std::to_string(kMaxSamples) + "], got " + std::to_string(s.samples));
  require(std::isfinite(s.filter_width) && (s.filter_width == 0.0f || (s.filter_width >= 0.01f && s.filter_width <= 10.0f)),
          "filter width must be 0 (the default, 1.5 pixels) or in [0.01, 10] pixels, got " +
              std::to_string(s.filter_width));
  require(s.first_sample >= 0 && s.first_sample <= 1000000,
          "first sample must be in [0, 1e6], got " + std::to_string(s.first_sample));
  require(s.shadow_resolution == 0 || (s.shadow_resolution >= 16 && s.shadow_resolution <= 8192),
          "shadow resolution must be 0 (automatic) or in [16, 8192], got " + std::to_string(s.shadow_resolution));
  if (s.shadow_resolution > maxTextureSize_)
    fail(SS_LIMIT_EXCEEDED, "shadow resolution " + std::to_string(s.shadow_resolution) +
                                " exceeds this GPU's texture limit of " + std::to_string(maxTextureSize_));
  require(s.precomputed_atlas == SS_ATLAS_UV_MAP || s.precomputed_atlas == SS_ATLAS_MADE,
          "precomputed atlas must be 0 (the UV map where it fits) or 1 (made), got " +
              std::to_string(s.precomputed_atlas));
  require(s.forward_shift == SS_FORWARD_SHIFT_ON || s.forward_shift == SS_FORWARD_SHIFT_OFF,
          "forward shift must be 0 (on) or 1 (off), got " + std::to_string(s.forward_shift));
  for (float c : s.background) require(std::isfinite(c), "background colour must be finite");
  settings_ = s;
  if (settings_.reference_samples == 0) settings_.reference_samples = kDefaultReferenceSamples;
  if (settings_.z0_factor == 0.0f) settings_.z0_factor = kDefaultZ0Factor;
  if (settings_.alpha == 0.0f) settings_.alpha = kDefaultAlpha;
  if (settings_.epsilon == 0.0f) settings_.epsilon = kDefaultEpsilon;
  if (settings_.lambda_z == 0.0f) settings_.lambda_z = kDefaultLambda;
  if (settings_.lambda_m == 0.0f) settings_.lambda_m = kDefaultLambda;
  if (settings_.target_error == 0.0f) settings_.target_error = kDefaultTargetError;
  if (settings_.samples == 0) settings_.samples = 1;
  if (settings_.filter_width == 0.0f) settings_.filter_width = kDefaultFilterWidth;
}

void Renderer::uploadMaterials(bool kernelTables) {
  scene_.resolveMaterials();
  gpuScene_.update(scene_);
  materialTables_.update(scene_, settings_.epsilon, kernelTables);
}

EnvironmentInputs Renderer::uploadEnvironment() {
  const Environment& environment = scene_.environment();
  if (uploadedEnvironment_ != scene_.environmentVersion()) {
    environmentTexture_.reset();
    if (environment) {
      const TextureImage& image = *environment.image;
      if (image.width() > maxTextureSize_ || image.height() > maxTextureSize_)
        fail(SS_LIMIT_EXCEEDED, "the environment image (" + std::to_string(image.width()) + " x " +
                                    std::to_string(image.height()) + ") exceeds this GPU's texture limit of " +
                                    std::to_string(maxTextureSize_));
      gl::Purpose purpose("the environment image (" + std::to_string(image.width()) + " x " +
                          std::to_string(image.height()) + " texels)");
      environmentTexture_ = gl::makeTexture2D(GL_RGBA16F, image.width(), image.height(), GL_LINEAR);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
      glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width(), image.height(), GL_RGB, GL_FLOAT,
                      &image.texels().front().x);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      gl::checkErrors("environment upload");
    }
    uploadedEnvironment_ = scene_.environmentVersion();
  }
  return {environment ? environmentTexture_.id() : 0u, environment.rotation, environment.strength};
}

void Renderer::countCoverage(int width, int height, const float* rgba, GLuint exitance) {
  size_t pixels = size_t(width) * height;
  for (size_t i = 0; i < pixels; ++i) {
    const float* out = rgba + 4 * i;
    if (!std::isfinite(out[0]) || !std::isfinite(out[1]) || !std::isfinite(out[2]) || !std::isfinite(out[3]))
      ++stats_.nonfinite_pixels;
  }
  CoverageCounts counts = coverage_.count(splatting_, exitance, int(scene_.denseMaterials().size()),
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
  // What the last render kept for the next edit serves only if nothing came between: a render
  // that fails or draws anything else leaves it invalid.
  const bool directWasKept = directKept_;
  directKept_ = false;
  // A budgeted render goes on where the last stopped when nothing changed since (the buffers and
  // the splatted levels are as it left them); it is invalid again until this one succeeds.
  bool budgeted = splatBudget_ > 0 && settings_.debug_passes == 0 && profiler_.countsFragments() &&
                  settings_.method != SS_METHOD_MATERIAL_EDIT && settings_.method != SS_METHOD_PRECOMPUTED;
  Resume resume = std::move(resume_);
  resume_ = Resume{};
  bool resuming = budgeted && resume.valid && resume.width == width && resume.height == height;
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

  // MATERIAL_EDIT (docs/MATERIAL_EDIT.md) selects and splats as FULL; a scene with a heterogeneous
  // material is FULL's. A render that reuses the transport splats nothing, at the precomputation's
  // resolution and levels (its direct light as the precomputation's), and needs no splat kernels.
  scene_.resolveMaterials();
  bool editing = settings_.method == SS_METHOD_MATERIAL_EDIT && !scene_.heterogeneous();
  // PRECOMPUTED (docs/PRECOMPUTED.md): FULL's buffers and direct light, its exitance relit from the
  // transport precomputed for these meshes and materials (precomputed again when they changed).
  const bool relit = settings_.method == SS_METHOD_PRECOMPUTED;
  bool reuse = editing && transportServes(width, height);
  if (editing && !reuse) precomputed_.valid = false;
  uploadMaterials(!reuse);
  const EnvironmentInputs environment = uploadEnvironment();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::STORAGE_MATERIALS, materialTables_.materials());
  bindTexture(gl::UNIT_TEXTURE_TEXELS, GL_TEXTURE_BUFFER, materialTables_.textureTexels());
  bool adaptive = settings_.method == SS_METHOD_ADAPTIVE || settings_.method == SS_METHOD_FULL ||
                  settings_.method == SS_METHOD_MATERIAL_EDIT;
  bool multires = settings_.method == SS_METHOD_MULTIRES || settings_.method == SS_METHOD_FULL ||
                  settings_.method == SS_METHOD_MATERIAL_EDIT;
  Bounds translucent = scene_.bounds(true), all = scene_.bounds(false);
  bool reachable = true;
  int resolution = settings_.irradiance_resolution > 0
                       ? settings_.irradiance_resolution
                       : chooseResolution(scene_, translucent, settings_.target_error, maxTextureSize_,
                                          nearestPixel(scene_, translucent, height), &reachable);
  Levels chosen = chooseLevels(scene_, settings_, width, height, translucent, resolution, adaptive, multires);
  if (reuse) resolution = precomputed_.resolution, chosen = {precomputed_.levels, precomputed_.splatLevels};
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
  if (editing) {
    gl::Purpose purpose("the material-edit transport (" + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels, " + std::to_string(splatLevels) + " levels, 2 x 8 RGBA32F layers each; lower the " +
                        "render resolution or use FULL)");
    transport_.resize(width, height, splatLevels);
    if (!reuse) transport_.clear();
  }
  gl::checkErrors("buffer allocation");

  stats_ = SsStats{};
  StageProfiler& profiler = profiler_;
  profiler.newFrame();
  // Anti-aliasing (docs/ANTIALIASING.md): the first sample is splatted; the others see the scene
  // through their own jittered cameras, with their own direct light, and the first's exitance.
  const SsCameraDesc camera = scene_.camera();
  CameraRestore restore{scene_, camera};
  int samples = settings_.samples;
  auto sampleCamera = [&](int s) {
    int index = settings_.first_sample + s;
    return index == 0 ? camera
                      : jitteredCamera(camera, pixelFilterOffset(index, settings_.filter_width), width, height);
  };
  const SsCameraDesc first = sampleCamera(0);
  scene_.setCamera(first);
  // Going on with one sample, the direct light is the first render's (anti-aliasing's other
  // samples draw theirs into the same buffer, so with them every render draws it again).
  // A material edit that leaves what the direct light reads as it was keeps the direct light of
  // the render before it (the precomputation's, or an edit's), and draws no light view. With
  // TABULATED materials, only where that render kept the light they send through thin parts.
  std::vector<double> directSignature;
  if (editing && samples == 1 && settings_.first_sample == 0) directSignature = this->directSignature();
  bool keptDirect = reuse && directWasKept && !directSignature.empty() && directSignature == directKeptFor_ &&
                    (!scene_.tabulated() || directThroughKept_);
  // Such an edit also keeps that render's camera G-buffer and its hierarchy: the geometry, the
  // camera and the size are the transport's (transportServes), the materials what the direct light
  // read (the signature), and any render between them, or a failed one, cleared directKept_.
  if (!resuming && !keptDirect) {
    profiler.begin(SS_STAGE_BUFFERS);
    splatting_.render(scene_, gpuScene_);
    splatting_.buildHierarchy(scene_.camera());
    splats_.clear();
    // The splats' depth test (pipeline/splat_depth.h), for the renders that splat.
    if (!relit && !editing && !translucent.empty()) splats_.prepareDepth(scene_, splatting_);
    if (editing && !reuse && !translucent.empty()) transport_.prepareDepth(scene_, splatting_);
    profiler.end();
    resume = Resume{};
  }
  bool reuseDirect = (resuming && samples == 1) || keptDirect;
  if (!reuseDirect) shading_.clear();
  gl::checkErrors("splatting buffer");

  Selection selection{levels, settings_.z0_factor * translucent.radius(), settings_.alpha,
                      settings_.forward_shift == SS_FORWARD_SHIFT_ON};
  KernelTables kernels = materialTables_.kernels();
  stats_.levels = levels;
  stats_.splat_levels = splatLevels;
  stats_.irradiance_resolution = resolution;
  stats_.target_reachable = reachable ? 1 : 0;
  double coarsest = lightTexel(scene_, translucent, resolution, false);
  stats_.texels_per_range = coarsest > 0.0 ? float(shortestRange(scene_) / coarsest) : 0.0f;
  int res = irradiance_.resolution();
  RenderLights lights = renderLights(scene_);
  std::vector<LightView> views;
  for (size_t i = 0; i < lights.lights.size(); ++i)
    for (LightView view : lightViews(lights.lights[i], translucent, all, res)) {
      if (lights.world[i]) view.worldDirections = &lights.worldDirections;
      views.push_back(view);
    }
  // Hard shadows on a map of their own resolution (docs/SOFT_SHADOWS.md, "Shadow maps").
  int shadowResolution = settings_.shadow_resolution > 0
                             ? settings_.shadow_resolution
                             : chooseShadowResolution(scene_, views, all, width, height, res, maxTextureSize_);
  bool ownShadowMap = shadowResolution != res;
  if (ownShadowMap) {
    gl::Purpose purpose("the shadow maps (" + std::to_string(shadowResolution) + " x " +
                        std::to_string(shadowResolution) + " texels; lower the shadow resolution)");
    shadowMap_.resize(shadowResolution);
  }
  stats_.shadow_resolution = shadowResolution;
  // A soft light's shadow on what enters translucent objects (docs/SOFT_SHADOWS.md, "Translucent
  // objects"): the irradiance buffer without opaque surfaces, filtered on a shadow map of every
  // surface drawn first: a sun's own shadow map, else one at the irradiance buffer's resolution.
  // Only where another object can cast it.
  bool softEntriesPossible = !translucent.empty() && scene_.meshes().size() > 1;
  bool softMapNeeded = false;
  for (const LightView& view : views)
    if (softEntriesPossible && view.softSize > 0.0f && (view.light->type != SS_LIGHT_SUN || !ownShadowMap))
      softMapNeeded = true;
  // PRECOMPUTED reads nothing of a light view but its shadows (its exitance is relit from the
  // precomputation): without TABULATED materials, whose light through thin parts reads where it
  // entered, a view is its shadow maps alone (docs/PRECOMPUTED.md, "A frame").
  const bool shadowsOnly = relit && !scene_.tabulated();
  if (shadowsOnly)
    for (const LightView& view : views)
      if (!ownShadowMap || (view.light->type != SS_LIGHT_SUN && view.softSize > 0.0f)) softMapNeeded = true;
  if (softMapNeeded) {
    gl::Purpose purpose("the soft shadows' maps (" + std::to_string(res) + " x " + std::to_string(res) +
                        " texels; lower the irradiance resolution)");
    softMap_.resize(res);
  }
  // Draws view i's maps and irradiance buffer; returns what the direct light reads of them.
  std::vector<char> softEntries(views.size(), 0);
  auto renderView = [&](size_t i) {
    const LightView& view = views[i];
    bool sun = view.light->type == SS_LIGHT_SUN, soft = softEntriesPossible && view.softSize > 0.0f;
    softEntries[i] = soft;
    SoftEntries entries;
    // A point, spot or area light's soft shadows never read the fine map.
    bool fine = ownShadowMap && (sun || view.softSize <= 0.0f);
    if (fine) shadowMap_.render(scene_, gpuScene_, view);
    if (shadowsOnly) {  // every surface at the irradiance's resolution where the fine map is not read
      ShadowInputs inputs;  // (no irradiance buffer's light depth: only the light through thin parts reads it)
      if (fine) {
        inputs.shadowDepth = shadowMap_.lightDepth(), inputs.shadowResolution = shadowResolution;
      } else {
        softMap_.render(scene_, gpuScene_, view);
        inputs.shadowDepth = inputs.lightDepth = inputs.softDepth = softMap_.lightDepth(), inputs.shadowResolution = res;
      }
      inputs.resolution = res;
      return inputs;
    }
    if (soft && sun && ownShadowMap) {
      entries = {shadowMap_.lightDepth(), shadowResolution};
    } else if (soft) {
      softMap_.render(scene_, gpuScene_, view);
      entries = {softMap_.lightDepth(), res};
    }
    if (relit)  // (TABULATED: the light through thin parts reads where it entered)
      irradiance_.renderEntries(scene_, gpuScene_, view, entries);
    else
      irradiance_.render(scene_, gpuScene_, view, entries);
    ShadowInputs inputs = irradiance_.shadowInputs();
    if (fine) inputs.shadowDepth = shadowMap_.lightDepth(), inputs.shadowResolution = shadowResolution;
    if (soft && !fine) inputs.shadowDepth = softMap_.lightDepth(), inputs.shadowResolution = res;
    if (soft && !sun) inputs.softDepth = softMap_.lightDepth();
    return inputs;
  };
  // The light TABULATED materials' direct light sends through thin parts, kept per view for the
  // edits that keep the direct light (Shading::keepThrough), within its memory.
  bool keptThrough = keptDirect ? directThroughKept_
                                : !directSignature.empty() && scene_.tabulated() && !translucent.empty() &&
                                      shading_.keepThrough(int(views.size()));
  // A render that reuses MATERIAL_EDIT's transport reads the precomputation's shadow maps: it draws
  // no light view the copies' budget kept (docs/MATERIAL_EDIT.md, "An edit").
  ShadowCopies& copies = editing ? editShadows_ : shadowCopies_;
  if (!reuse) copies.reset();
  SplatBudget budget;
  budget.fragments = splatBudget_;
  bool splatsStopped = false;
  for (size_t i = 0; i < views.size(); ++i) {
    const LightView& view = views[i];
    // Going on (docs/VIEWPORT.md): the direct light is the first render's; only the views still
    // to splat are drawn again, while the budget lasts.
    if (keptDirect) break;
    if (reuseDirect && (i < resume.view || splatsStopped || translucent.empty())) continue;
    const ShadowInputs* kept = reuse ? copies.find(i) : nullptr;
    ShadowInputs inputs;
    if (kept) {
      inputs = *kept;
    } else {
      profiler.begin(SS_STAGE_BUFFERS);
      inputs = renderView(i);
      if (samples > 1 || (editing && !reuse)) copies.keep(i, inputs, scene_.tabulated());
      if (scene_.tabulated() && !relit)  // (the flux's incidence factor: PRECOMPUTED splats no flux)
        irradiance_.applyIncidence(scene_, gpuScene_, view, kernels.transport, softEntries[i] != 0);
      if (adaptive && !reuse) irradiance_.buildHierarchy();
      profiler.end();
    }
    if (relit) {
      // no splats: the exitance is the precomputed transport's
    } else if (!translucent.empty() && editing) {
      if (!reuse) transport_.splat(scene_, view, irradiance_, splatting_, kernels, selection, profiler);
    } else if (!translucent.empty() && !budgeted) {
      splats_.splat(scene_, view, irradiance_, splatting_, kernels, selection, profiler);
    } else if (!translucent.empty() && i == resume.view && !splatsStopped) {
      if (splats_.splat(scene_, view, irradiance_, splatting_, kernels, selection, profiler, &resume.cursor, &budget))
        resume.view = i + 1, resume.cursor = SplatCursor{};
      else
        splatsStopped = true;
    }
    if (!reuseDirect) {
      profiler.begin(SS_STAGE_SHADING);
      shading_.directLighting(scene_, view, inputs, splatting_, kernels.transport, keptThrough ? int(i) : -1);
      profiler.end();
    }
    ++stats_.light_views;
    gl::checkErrors("light view");
  }
  Accumulation accumulation{settings_.lambda_z, settings_.lambda_m, 2.0f * translucent.radius()};
  if (!translucent.empty() && editing) {
    if (!reuse) {
      transport_.accumulate(scene_, splatting_, accumulation, profiler);
      stats_.splat_count = transport_.readSelectionCounts(stats_.selected_per_level);
      recordPrecomputation(width, height, resolution, levels, splatLevels, camera);
      transport_.storeFactors(splatting_, kernels.transport);
    }
    profiler.begin(SS_STAGE_SHADING);
    transport_.combine(splatting_, editCoefficients(), kernels.transport);
    profiler.end();
  } else if (relit) {
    renderPrecomputed(width, height);
  } else if (!translucent.empty()) {  // (one level: only keeps the debug copy)
    splats_.accumulate(scene_, splatting_, accumulation, profiler, budgeted);
    stats_.splat_count = splats_.readSelectionCounts(stats_.selected_per_level);
  }
  const GLuint exitanceTexture = relit ? precomputedDisplay_.exitance() : editing ? transport_.exitance() : splats_.exitance();
  float weight = 1.0f / float(samples);
  profiler.begin(SS_STAGE_SHADING);
  if (keptThrough) shading_.addKeptThrough(splatting_, kernels.transport);
  shading_.finalShading(scene_, splatting_, exitanceTexture, kernels.transport, settings_.background, environment,
                        lights, samples > 1 ? weight : 1.0f, true);
  profiler.end();

  if (samples > 1) {
    gl::Purpose purpose("the anti-aliasing buffers (" + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels; lower the render resolution)");
    sampleBuffer_.resize(width, height, 1);
    reprojection_.resize(width, height);
  }
  for (int s = 1; s < samples; ++s) {
    scene_.setCamera(sampleCamera(s));
    profiler.begin(SS_STAGE_BUFFERS);
    sampleBuffer_.render(scene_, gpuScene_);
    profiler.end();
    shading_.clear();
    // Each view's shadow map as the first sample kept it; one past the copies' budget is drawn again.
    for (size_t i = 0; i < views.size(); ++i) {
      const ShadowInputs* kept = copies.find(i);
      ShadowInputs drawn;
      if (kept == nullptr) {
        profiler.begin(SS_STAGE_BUFFERS);
        drawn = renderView(i);
        profiler.end();
        ++stats_.light_views;
      }
      profiler.begin(SS_STAGE_SHADING);
      shading_.directLighting(scene_, views[i], kept ? *kept : drawn, sampleBuffer_, kernels.transport);
      profiler.end();
      gl::checkErrors("anti-aliasing sample");
    }
    profiler.begin(SS_STAGE_SHADING);
    GLuint exitance = 0;
    if (!translucent.empty()) {
      reprojection_.reproject(first, splatting_, exitanceTexture, scene_.camera(), sampleBuffer_);
      exitance = reprojection_.exitance();
    } else {
      exitance = exitanceTexture;  // no translucent pixel reads it
    }
    shading_.finalShading(scene_, sampleBuffer_, exitance, kernels.transport, settings_.background, environment,
                          lights, weight, false);
    profiler.end();
  }
  scene_.setCamera(camera);
  stats_.samples = samples;

  profiler.begin(SS_STAGE_READBACK);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, shading_.resultFramebuffer());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba);
  profiler.end();
  gl::checkErrors("read-back");
  profiler.collect(stats_);
  countCoverage(width, height, rgba, exitanceTexture);
  stats_.width = width;
  stats_.height = height;
  if (!directSignature.empty()) {
    directKept_ = true;
    directKeptFor_ = std::move(directSignature);
    directThroughKept_ = keptThrough;
  }
  bool complete = !budgeted || translucent.empty() || resume.view >= views.size();
  stats_.splatting_complete = complete ? 1 : 0;
  if (!complete) {  // views done, and of the view under way its levels done and its level's share
    double total = std::max(splats_.lastSampleCount(), 1);
    double inView = (resume.cursor.level + resume.cursor.first / total) / double(splatLevels);
    stats_.splatting_progress = float((double(resume.view) + inView) / double(views.size()));
  } else {
    stats_.splatting_progress = 1.0f;
  }
  if (budgeted && !complete) {
    resume.valid = true, resume.width = width, resume.height = height;
    resume_ = std::move(resume);
  }
  stats_.frame_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!relit) stats_.transport_reused = reuse ? 1 : 0;
  lastFromTransport_ = editing;
  stats_.transport_full_pipeline = settings_.method == SS_METHOD_MATERIAL_EDIT && !editing ? 1 : 0;
  if (editing && !reuse) {
    stats_.precompute_ms = stats_.frame_ms;
    precomputed_.valid = true;
  }
  lastMethod_ = settings_.method, lastWidth_ = width, lastHeight_ = height;
}

void Renderer::renderPrecomputed(int width, int height) {
  using Clock = std::chrono::steady_clock;
  {
    gl::Purpose purpose("PRECOMPUTED's exitance (" + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels; lower the render resolution)");
    precomputedDisplay_.resize(width, height);
  }
  const bool ownUvs = settings_.precomputed_atlas == SS_ATLAS_UV_MAP;
  bool reuse = precomputedTransport_.serves(scene_, ownUvs);
  auto start = Clock::now();
  if (!reuse) {
    // Within the memory budget, less what the frame's GPU buffers already hold.
    uint64_t budget = gl::memoryBudget(), live = gl::gpuBytes();
    size_t room = size_t(std::min<uint64_t>(budget > live ? budget - live : 0, PrecomputedTransport::kDefaultBytes));
    try {
      precomputedTransport_.precompute(scene_, room, progress_, ownUvs);
    } catch (...) {
      precomputedTransport_.clear();
      throw;
    }
    stats_.precompute_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  }
  auto relightStart = Clock::now();
  precomputedTransport_.relight(scene_, progress_, settings_.forward_shift == SS_FORWARD_SHIFT_ON);
  stats_.relight_ms = std::chrono::duration<double, std::milli>(Clock::now() - relightStart).count();
  stats_.transport_reused = reuse ? 1 : 0;
  for (const SsPrecomputedObject& o : precomputedObjects())
    stats_.precomputed_bytes += o.bytes, stats_.precomputed_texels += o.texels, stats_.precomputed_factors += o.factors;
  precomputedDisplay_.draw(precomputedTransport_, scene_, scene_.camera());
}

std::vector<SsPrecomputedObject> Renderer::precomputedObjects() const {
  std::vector<SsPrecomputedObject> result;
  for (const PrecomputedTransport::Object& o : precomputedTransport_.objects()) {
    SsPrecomputedObject p{};
    p.object_id = o.objectId;
    p.vertices = uint32_t(o.vertices);
    p.bytes = o.bytes();
    p.texels = o.active.size();
    p.kernel_taps = o.kernelSource.size();
    p.factors = o.factors();
    p.atlas_width = o.atlas.width, p.atlas_height = o.atlas.height;
    p.charts = o.atlas.charts, p.uv_charts = o.atlas.uvCharts, p.uv_islands_refused = o.atlas.uvIslandsRefused;
    p.texel_size = o.atlas.texel;
    p.local_range = o.size.localRange;
    p.precompute_ms = o.precomputeMs;
    result.push_back(p);
  }
  std::sort(result.begin(), result.end(), [](const auto& a, const auto& b) { return a.object_id < b.object_id; });
  return result;
}

void Renderer::recordPrecomputation(int width, int height, int resolution, int levels, int splatLevels,
                                    const SsCameraDesc& camera) {
  Precomputed& p = precomputed_;
  p.width = width, p.height = height, p.resolution = resolution, p.levels = levels, p.splatLevels = splatLevels;
  p.camera = camera;
  p.settings = settings_;
  p.geometry = scene_.geometryVersion(), p.environment = scene_.environmentVersion();
  p.entries.clear();
  for (const MaterialEntry& m : scene_.denseMaterials()) {
    Precomputed::Entry e;
    e.id = m.id;
    e.translucent = m.kernel != nullptr;
    if (m.kernel) {
      const auto& ranges = m.kernel->effectiveRange();
      e.range = std::max({ranges[0], ranges[1], ranges[2]});
      e.mmPerUnit = m.kernel->mmPerUnit();
      e.reach = std::min(kEditReach * e.range, double(TransportSplatting::kSupportGrowth) * m.kernel->supportRadius());
      DipoleMaterial medium = dipoleMaterial(m.desc);
      for (int c = 0; c < 3; ++c) e.eta[size_t(c)] = medium.channels[size_t(c)].eta;
      e.entering = enteringSignature(m);
    }
    p.entries.push_back(e);
  }
}

bool Renderer::transportServes(int width, int height) const {
  const Precomputed& p = precomputed_;
  if (!p.valid || p.width != width || p.height != height) return false;
  if (std::memcmp(&p.camera, &scene_.camera(), sizeof p.camera) != 0) return false;
  if (std::memcmp(&p.settings, &settings_, sizeof p.settings) != 0) return false;
  if (p.geometry != scene_.geometryVersion() || p.environment != scene_.environmentVersion()) return false;
  const auto& dense = scene_.denseMaterials();
  if (dense.size() != p.entries.size()) return false;
  for (size_t i = 0; i < dense.size(); ++i) {
    const MaterialEntry& m = dense[i];
    const Precomputed::Entry& e = p.entries[i];
    if (m.id != e.id || (m.kernel != nullptr) != e.translucent) return false;
    if (!m.kernel) continue;
    // The Fresnel transmittance at entry is in the transport, splatted as far as e.reach.
    DipoleMaterial medium = dipoleMaterial(m.desc);
    for (int c = 0; c < 3; ++c)
      if (medium.channels[size_t(c)].eta != e.eta[size_t(c)]) return false;
    if (m.kernel->mmPerUnit() != e.mmPerUnit || m.kernel->supportRadius() > e.reach) return false;
    if (enteringSignature(m) != e.entering) return false;
  }
  return true;
}

namespace {

// A texture's image (by identity) and how the mesh's UVs read it.
void appendTexture(std::vector<double>& signature, const Texture& t) {
  signature.push_back(double(reinterpret_cast<uintptr_t>(t.image.get())));
  signature.insert(signature.end(), std::begin(t.transform), std::end(t.transform));
  signature.push_back(t.extension);
  signature.push_back(t.interpolation);
}

}  // namespace

std::vector<double> Renderer::enteringSignature(const MaterialEntry& m) {
  std::vector<double> signature{double(m.desc.normal_strength), double(m.desc.profile_model)};
  appendTexture(signature, m.color);
  appendTexture(signature, m.normal);
  return signature;
}

std::vector<double> Renderer::directSignature() const {
  std::vector<double> signature;
  for (const MaterialEntry& m : scene_.denseMaterials()) {
    const SsMaterialDesc& d = m.desc;
    signature.insert(signature.end(), {double(d.kind), d.base_color[0], d.base_color[1], d.base_color[2], d.eta,
                                       d.mm_per_unit, d.roughness, d.specular});
    std::vector<double> entering = enteringSignature(m);  // the profile model, normal map and textures
    signature.insert(signature.end(), entering.begin(), entering.end());
  }
  return signature;
}

std::vector<EditCoefficients> Renderer::editCoefficients() const {
  const ProfileBasis& basis = TransportSplatting::basis();
  const auto& dense = scene_.denseMaterials();
  std::vector<EditCoefficients> result(dense.size());
  for (size_t i = 0; i < dense.size(); ++i) {
    const MaterialEntry& m = dense[i];
    if (!m.kernel || i >= precomputed_.entries.size()) continue;
    const Precomputed::Entry& e = precomputed_.entries[i];
    const SplatKernel& kernel = *m.kernel;
    for (int c = 0; c < 3; ++c) {
      // The channel as the splatting uses it (cut at the support, renormalised), in R_P units.
      std::shared_ptr<const RadialProfile> channel(m.kernel, &kernel.channel(c));
      SupportedProfile cut(channel, kernel.supportRadius() * kernel.mmPerUnit());
      std::vector<double> coefficients = basis.project({&cut, e.range * e.mmPerUnit});
      for (int j = 0; j < EditCoefficients::kSplines; ++j) result[i].spline[j][c] = float(coefficients[size_t(j)]);
    }
  }
  return result;
}

void Renderer::renderReference(int width, int height, float* rgba) {
  scene_.resolveMaterials();
  ReferenceOptions options;
  options.samples = settings_.reference_samples;
  options.background = glm::make_vec4(settings_.background);
  options.pixelSamples = settings_.samples;
  options.firstSample = settings_.first_sample;
  options.filterWidth = settings_.filter_width;
  options.forwardShift = settings_.forward_shift == SS_FORWARD_SHIFT_ON;
  SsStats stats{};
  reference_.render(scene_, options, width, height, rgba, progress_, stats);
  stats_ = stats;
  stats_.splatting_complete = 1;  // no budget: REFERENCE is for final renders
  stats_.target_reachable = 1;      // no irradiance buffers
  stats_.splatting_progress = 1.0f;
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
  if (lastMethod_ == SS_METHOD_MATERIAL_EDIT || lastMethod_ == SS_METHOD_PRECOMPUTED)
    require(pass == SS_PASS_EXITANCE, std::string(lastMethod_ == SS_METHOD_PRECOMPUTED ? "PRECOMPUTED" : "MATERIAL_EDIT") +
                                          " has only the exitance pass");
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
  glBindTexture(GL_TEXTURE_2D, lastMethod_ == SS_METHOD_PRECOMPUTED ? precomputedDisplay_.exitance()
                               : lastFromTransport_                  ? transport_.exitance()
                                                                     : splats_.exitance());
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
