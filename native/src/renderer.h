// One frame: buffer generation, splatting, shading, read-back.
#pragma once

#include "pipeline/coverage.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/material_tables.h"
#include "pipeline/reprojection.h"
#include "pipeline/shadow_map.h"
#include "pipeline/shading.h"
#include "pipeline/splatting.h"
#include "pipeline/splatting_buffer.h"
#include "pipeline/stage_profiler.h"
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
  void setProgress(ProgressFunction progress) { progress_ = std::move(progress); }
  // A pass of the last successful render (SsPass), width x height RGBA.
  void readPass(int pass, int width, int height, float* rgba);

 private:
  // Resolves the scene's materials and brings the GPU's copy and the tables up to date.
  void uploadMaterials();
  // The environment's map, uploaded when it changed; the inputs of the final shading.
  EnvironmentInputs uploadEnvironment();
  // Coverage figures of the frame for SsStats (tests and the UI read them): non-finite
  // pixels of the image, translucent and lit translucent pixels counted on the GPU.
  void countCoverage(int width, int height, const float* rgba);
  void renderReference(int width, int height, float* rgba);

  Scene scene_;
  GpuScene gpuScene_;  // follows scene_ (its mesh observer)
  SsSettings settings_ = ssDefaultSettings();
  SsStats stats_{};
  IrradianceBuffer irradiance_;
  SplattingBuffer splatting_;      // the first sample's
  SplattingBuffer sampleBuffer_;   // the other samples' (anti-aliasing), one at a time
  ExitanceReprojection reprojection_;
  ShadowCopies shadowCopies_;      // the first sample's shadow maps, for the others
  ShadowMap shadowMap_;            // the hard shadows' map, when its resolution is not the irradiance's
  ShadowMap softMap_;              // every surface at the irradiance's resolution, for SoftEntries
  Splatting splats_;
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
};

}  // namespace subsplat
