#include "pipeline/auto_quality.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "pipeline/light_views.h"
#include "world_light.h"

namespace subsplat {

double shortestRange(const Scene& scene) {
  double range = 0.0;
  for (const MaterialEntry& m : scene.denseMaterials()) {
    if (!m.kernel) continue;
    for (double r : m.kernel->effectiveRange())
      if (r > 0.0) range = range > 0.0 ? std::min(range, r) : r;
  }
  return range;
}

double lightTexel(const Scene& scene, const Bounds& translucent, int resolution, bool finest) {
  double texel = 0.0;
  if (translucent.empty()) return texel;
  Bounds all = scene.bounds(false);
  RenderLights lights = renderLights(scene);
  for (const SsLightDesc& light : lights.lights)
    for (const LightView& view : lightViews(light, translucent, all, resolution)) {
      double size = light.type == SS_LIGHT_SUN
                        ? view.shadowTexelSize
                        : view.shadowTexelSize * glm::distance(glm::make_vec3(light.position), translucent.center());
      size = std::max(size, 1e-12);
      texel = texel == 0.0 ? size : finest ? std::min(texel, size) : std::max(texel, size);
    }
  return texel;
}

double texelsAcrossFor(double targetError) {
  return kRuleTexels * std::pow(kRuleError / targetError, 1.0 / kRulePower);
}

double shortestRadius(const Scene& scene, double energy) {
  double radius = 0.0;
  for (const MaterialEntry& m : scene.denseMaterials()) {
    if (!m.kernel) continue;
    for (int c = 0; c < 3; ++c) {
      double r = m.kernel->channel(c).radiusForEnergy(energy) / m.kernel->mmPerUnit();
      if (r > 0.0) radius = radius > 0.0 ? std::min(radius, r) : r;
    }
  }
  return radius;
}

double nearestPixel(const Scene& scene, const Bounds& translucent, int height) {
  if (translucent.empty() || height <= 0) return 0.0;
  const SsCameraDesc& camera = scene.camera();
  glm::mat4 proj = glm::make_mat4(camera.view_to_clip);
  glm::vec4 centre = glm::make_mat4(camera.world_to_view) * glm::vec4(translucent.center(), 1.0f);
  double depth = std::max(double(-centre.z) - translucent.radius(), 1e-6);
  double extent = camera.orthographic ? 2.0 / proj[1][1] : 2.0 * depth / proj[1][1];
  return extent / double(height);
}

double ruleLength(const Scene& scene, double pixel) {
  // At R_P's energy the kernels' cached ranges serve; another energy is searched for per channel
  // (a bisection each) every frame.
  double radius = kRuleEnergy == SplatKernel::kEffectiveRangeEnergy ? shortestRange(scene) : shortestRadius(scene, kRuleEnergy);
  return radius > 0.0 ? std::max(radius, kRulePixels * pixel) : 0.0;
}

int chooseResolution(const Scene& scene, const Bounds& translucent, double targetError, int maxTextureSize,
                     double pixel, bool* reachable) {
  // Texels grow with 1 / resolution, so one probe gives the texels per R_P at every
  // resolution. The rungs step by 1.33-1.5 in texels across (about sqrt(2)), about 2 in work.
  constexpr int kProbe = 512;
  static constexpr int kRungs[] = {128, 192, 256, 384, 512, 768, 1024, 1536, 2048};
  int most = std::min(kAutoResolutionMax, maxTextureSize);
  if (reachable) *reachable = true;
  double length = ruleLength(scene, pixel), texel = lightTexel(scene, translucent, kProbe, false);
  if (!(length > 0.0) || !(texel > 0.0)) return kAutoResolutionMin;  // nothing translucent is lit
  double needed = kProbe * texelsAcrossFor(targetError) * texel / length;
  for (int rung : kRungs)
    if (rung >= needed && rung <= most) return std::max(rung, kAutoResolutionMin);
  if (reachable) *reachable = false;
  return most;
}

Levels chooseLevels(const Scene& scene, const SsSettings& settings, int width, int height,
                    const Bounds& translucent, int resolution, bool adaptive, bool multires) {
  Levels levels;
  int maxIrradiance = 1, maxSplat = 1;  // while the coarsest level keeps a texel / pixel
  // (and while each level halves the one above exactly: 192 keeps 7 levels, down to 3 x 3)
  while (maxIrradiance < 8 && (resolution >> maxIrradiance) >= 1 && resolution % (1 << maxIrradiance) == 0)
    ++maxIrradiance;
  while (maxSplat < 8 && (std::max(width, height) >> maxSplat) >= 1) ++maxSplat;
  if (settings.levels > 0) {
    levels.irradiance = adaptive ? std::min(settings.levels, maxIrradiance) : 1;
    levels.splat = multires ? std::min(settings.levels, maxSplat) : 1;
    return levels;
  }
  if (translucent.empty()) return levels;
  double rangeMin = shortestRange(scene), rangeMax = 0.0;  // R_P over the translucent materials' channels
  for (const MaterialEntry& m : scene.denseMaterials()) {
    if (!m.kernel) continue;
    for (double r : m.kernel->effectiveRange()) rangeMax = std::max(rangeMax, r);
  }
  if (!(rangeMax > 0.0)) return levels;
  auto clampLevels = [](double log2Ratio, int most) {
    return std::clamp(1 + int(std::floor(std::max(log2Ratio, 0.0))), 1, most);
  };
  if (adaptive) {
    // The finest texel any light view puts on the translucent objects, and the coarsest
    // level at which such a texel, facing the light, could still be fine enough (eq. 11).
    double texel = lightTexel(scene, translucent, resolution, true);
    if (texel > 0.0) levels.irradiance = clampLevels(std::log2(rangeMin / (settings.alpha * texel)), maxIrradiance);
  }
  if (multires) {
    // The coarsest splatting level keeps kCoarsestPixelsPerRange pixels per R_P (the longest
    // channel's) at the translucent objects' nearest depth. It takes the profile's tail beyond
    // R_P, a ring 0.8 R_P wide: coarser than that, upsampling blurs the ring across
    // silhouettes and the error grows while the work hardly falls, since with eq. 14's
    // epsilon the finest level keeps most of [0, R_P) anyway (docs/MULTIRES.md).
    double pixel = nearestPixel(scene, translucent, height);
    levels.splat = clampLevels(std::log2(rangeMax / (kCoarsestPixelsPerRange * pixel)), maxSplat);
  }
  return levels;
}

}  // namespace subsplat
