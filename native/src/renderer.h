// One frame: buffer generation, splatting, shading, read-back.
#pragma once

#include "pipeline/coverage.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/material_tables.h"
#include "pipeline/precomputed_display.h"
#include "pipeline/reprojection.h"
#include "pipeline/shadow_map.h"
#include "pipeline/shading.h"
#include "pipeline/splatting.h"
#include "pipeline/splatting_buffer.h"
#include "pipeline/stage_profiler.h"
#include "pipeline/transport_splatting.h"
#include "reference/reference_renderer.h"
#include "scene.h"

namespace subsplat {

class Renderer {
 public:
  static constexpr uint32_t kDefaultReferenceSamples = 200000;
  static constexpr int kDefaultLevels = 0;  // automatic
  static constexpr float kDefaultZ0Factor = 0.03f, kDefaultAlpha = 15.0f, kDefaultEpsilon = 0.001f;
  static constexpr float kDefaultLambda = 8.0f;
  // Automatic irradiance resolution (pipeline/auto_quality.h, docs/AUTO.md).
  static constexpr float kDefaultTargetError = 0.01f;
  // Anti-aliasing (docs/ANTIALIASING.md): Blender's default pixel filter width, and the most samples.
  static constexpr float kDefaultFilterWidth = 1.5f;
  static constexpr int kMaxSamples = 1024;
  Renderer();
  // Any change through the scene restarts a budgeted render's splatting (setCamera: a different camera).
  Scene& scene() {
    resume_.valid = false;
    return scene_;
  }
  void setCamera(const SsCameraDesc& camera);
  // At most this many splatting fragment invocations per render (0: no budget; docs/VIEWPORT.md,
  // "Progressive splatting"): a render that runs out leaves the rest of the splats to the next,
  // which goes on where it stopped while nothing changed; SsStats.splatting_complete says which.
  void setSplatBudget(uint64_t fragments) {
    splatBudget_ = fragments;
    resume_.valid = false;
  }
  const Scene& scene() const { return scene_; }
  void setSettings(const SsSettings& settings);
  const SsSettings& settings() const { return settings_; }
  // Size of the last successful render, 0 x 0 before the first.
  int lastWidth() const { return lastWidth_; }
  int lastHeight() const { return lastHeight_; }
  void render(int width, int height, float* rgba);
  const SsStats& stats() const { return stats_; }
  // PRECOMPUTED's objects, in ascending id (ssGetPrecomputedObjects).
  std::vector<SsPrecomputedObject> precomputedObjects() const;
  void setProgress(ProgressFunction progress) { progress_ = std::move(progress); }
  // A pass of the last successful render (SsPass), width x height RGBA.
  void readPass(int pass, int width, int height, float* rgba);

 private:
  // Resolves the scene's materials and brings the GPU's copy and the tables up to date (without
  // kernelTables: all but the splat kernels and R-bar, for a render that splats nothing).
  void uploadMaterials(bool kernelTables = true);
  // The environment's map, uploaded when it changed; the inputs of the final shading.
  EnvironmentInputs uploadEnvironment();
  // Coverage figures of the frame for SsStats (tests and the UI read them): non-finite
  // pixels of the image, translucent and lit translucent pixels counted on the GPU.
  void countCoverage(int width, int height, const float* rgba, GLuint exitance);
  void renderReference(int width, int height, float* rgba);
  // PRECOMPUTED's exitance (precomputedDisplay_), precomputing first when the transport does not
  // serve the scene's meshes and materials.
  void renderPrecomputed(int width, int height);

  Scene scene_;
  GpuScene gpuScene_;  // follows scene_ (its mesh observer)
  SsSettings settings_ = ssDefaultSettings();
  SsStats stats_{};
  IrradianceBuffer irradiance_;
  SplattingBuffer splatting_;      // the first sample's
  SplattingBuffer sampleBuffer_;   // the other samples' (anti-aliasing), one at a time
  ExitanceReprojection reprojection_;
  ShadowCopies shadowCopies_;      // the first sample's shadow maps, for the others
  ShadowCopies editShadows_;       // MATERIAL_EDIT's: the precomputation's, for its edits' direct light
  ShadowMap shadowMap_;            // the hard shadows' map, when its resolution is not the irradiance's
  ShadowMap softMap_;              // every surface at the irradiance's resolution, for SoftEntries
  Splatting splats_;
  TransportSplatting transport_;   // MATERIAL_EDIT's
  PrecomputedTransport precomputedTransport_;  // PRECOMPUTED's (docs/PRECOMPUTED.md)
  PrecomputedDisplay precomputedDisplay_;
  Shading shading_;
  Coverage coverage_;
  StageProfiler profiler_;  // its queries are reused by every frame of this context
  MaterialTables materialTables_;
  // The scene's environment on the GPU (RGBA16F), of environment version uploadedEnvironment_.
  gl::Texture environmentTexture_;
  uint64_t uploadedEnvironment_ = ~0ull;
  GLint maxTextureSize_ = 0;
  ReferenceRenderer reference_;
  ProgressFunction progress_;
  int lastMethod_ = -1, lastWidth_ = 0, lastHeight_ = 0;  // of the last successful render
  bool lastFromTransport_ = false;  // its exitance is MATERIAL_EDIT's (transport_), not splats_'s
  // Where a budgeted render's splatting stopped: light view, and level and sample within it. Valid
  // after a budgeted render that stopped early, until anything changes.
  struct Resume {
    bool valid = false;
    int width = 0, height = 0;
    size_t view = 0;
    SplatCursor cursor;
  };
  uint64_t splatBudget_ = 0;
  Resume resume_;
  // MATERIAL_EDIT (docs/MATERIAL_EDIT.md): what the transport in transport_ was precomputed for.
  // It serves a render while the size, camera, settings, meshes, lights and environment are the
  // same and every material can be projected onto its basis (transportServes).
  struct Precomputed {
    bool valid = false;
    int width = 0, height = 0, resolution = 0, levels = 0, splatLevels = 0;
    SsCameraDesc camera{};
    SsSettings settings{};
    uint64_t geometry = 0, environment = 0;
    struct Entry {
      uint32_t id = 0;
      bool translucent = false;
      double range = 0.0, mmPerUnit = 1.0;  // R_P (the longest channel's), scene units
      double reach = 0.0;  // how far the transport was splatted, scene units (kSupportGrowth)
      std::array<double, 3> eta{};
      // What the entering light carries besides the index of refraction (enteringSignature).
      std::vector<double> entering;
    };
    std::vector<Entry> entries;
  };
  Precomputed precomputed_;  // valid once the render that precomputed it has succeeded
  // The direct light in shading_ as the last render left it, when that render was MATERIAL_EDIT's
  // with one unjittered sample: the precomputation's camera, lights and meshes, and materials of
  // signature directKeptFor_ (directSignature). An edit that changes none of what the direct light
  // reads but a material's absorption and scattering draws no light view. With TABULATED
  // materials, whose direct light sends light through thin parts, only if that render kept that
  // light before the slab's transmission (directThroughKept_: Shading::keepThrough).
  bool directKept_ = false, directThroughKept_ = false;
  std::vector<double> directKeptFor_;
  // What the direct light reads of the materials (direct_lighting.frag), but the absorption and
  // scattering: every field, and (enteringSignature) the textures' images by identity.
  std::vector<double> directSignature() const;
  // What the light entering a translucent entry carries in the irradiance buffers, and so in the
  // transport, besides the index of refraction (irradiance_buffer.frag): the colour texture's tint
  // and the normal map's normal; and the profile model, whose incidence factor and side weight
  // (TABULATED) the precomputation splats.
  static std::vector<double> enteringSignature(const MaterialEntry& m);
  bool transportServes(int width, int height) const;
  // What the transport splatted this render was precomputed for (camera: the host's).
  void recordPrecomputation(int width, int height, int resolution, int levels, int splatLevels,
                            const SsCameraDesc& camera);
  // The dense entries' coefficients on the precomputed basis (transport_combine.frag).
  std::vector<EditCoefficients> editCoefficients() const;
};

}  // namespace subsplat
