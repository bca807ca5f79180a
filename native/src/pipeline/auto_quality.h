// The automatic quality (docs/AUTO.md, docs/MULTIRES.md): the irradiance
// resolution from the target error, and the irradiance and splatting levels
// from the scattering ranges. Plain CPU code over the scene.
#pragma once

#include "scene.h"

namespace subsplat {

// Automatic levels: pixels per R_P the coarsest splatting level keeps (chooseLevels).
constexpr double kCoarsestPixelsPerRange = 8.0;
// Automatic irradiance resolution (docs/AUTO.md).
constexpr int kAutoResolutionMin = 128, kAutoResolutionMax = 2048;

// Irradiance texels across the shortest R_P an automatic resolution gives for a target
// relative RMSE: the error model fitted on the example scenes (docs/AUTO.md).
double texelsPerRangeFor(double targetError);

// The shortest effective range R_P over the translucent materials' channels (0: none).
// The scene's materials must be resolved.
double shortestRange(const Scene& scene);
// The world size of the finest (finest = true) or coarsest texel the light views put on
// the translucent objects at a resolution (0: no light).
double lightTexel(const Scene& scene, const Bounds& translucent, int resolution, bool finest);
// The automatic irradiance resolution for a target error, at most maxTextureSize.
int chooseResolution(const Scene& scene, const Bounds& translucent, double targetError, int maxTextureSize);

struct Levels {
  int irradiance = 1, splat = 1;
};
// settings.levels, or (0) levels chosen from the ranges; adaptive: irradiance levels,
// multires: splatting levels.
Levels chooseLevels(const Scene& scene, const SsSettings& settings, int width, int height,
                    const Bounds& translucent, int resolution, bool adaptive, bool multires);

}  // namespace subsplat
