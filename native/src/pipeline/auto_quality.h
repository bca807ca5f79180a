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

// The automatic resolution's rule (docs/AUTO.md): the coarsest light texel must put
// texelsAcrossFor(target) texels across ruleLength: the radius holding kRuleEnergy of the shortest
// profile's energy, or kRulePixels pixels at the translucent objects where that is longer (finer
// detail than that the image cannot show). The error the irradiance sampling adds over a converged buffer's is at most
// kRuleError * (t / kRuleTexels)^-kRulePower on every calibration point, t those texels: fitted on
// the calibration set of procedural scenes (bench/auto_sets.sh, bench/auto_fit.py).
constexpr double kRuleEnergy = 0.95, kRulePixels = 0.0, kRuleError = 0.01, kRuleTexels = 1.5, kRulePower = 2.0;
// Texels across that radius an automatic resolution gives for a target relative RMSE.
double texelsAcrossFor(double targetError);

// The shortest effective range R_P over the translucent materials' channels (0: none).
// The scene's materials must be resolved.
double shortestRange(const Scene& scene);
// The shortest radius holding `energy` of a translucent material's channel's profile (0: none).
double shortestRadius(const Scene& scene, double energy);
// The world size of the finest (finest = true) or coarsest texel the light views put on
// the translucent objects at a resolution (0: no light).
double lightTexel(const Scene& scene, const Bounds& translucent, int resolution, bool finest);
// A pixel's size, in scene units, at the translucent objects' nearest depth (the near side of their
// bounds' sphere) in an image `height` pixels high.
double nearestPixel(const Scene& scene, const Bounds& translucent, int height);
// The length the rule puts its texels across: the radius holding kRuleEnergy of the shortest
// profile's energy, or kRulePixels pixels where that is finer (0: none translucent).
double ruleLength(const Scene& scene, double pixel);
// The automatic irradiance resolution for a target error, at most maxTextureSize, for pixels of
// `pixel` scene units at the translucent objects; *reachable (when given) is false when the target
// needs more than that.
int chooseResolution(const Scene& scene, const Bounds& translucent, double targetError, int maxTextureSize,
                     double pixel, bool* reachable = nullptr);

struct Levels {
  int irradiance = 1, splat = 1;
};
// settings.levels, or (0) levels chosen from the ranges; adaptive: irradiance levels,
// multires: splatting levels.
Levels chooseLevels(const Scene& scene, const SsSettings& settings, int width, int height,
                    const Bounds& translucent, int resolution, bool adaptive, bool multires);

}  // namespace subsplat
