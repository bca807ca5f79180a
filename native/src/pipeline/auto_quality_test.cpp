// The automatic quality without a GL context: resolution rungs that meet the
// error model's texels per R_P, and levels that follow the scattering ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pipeline/auto_quality.h"
#include "scene.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

constexpr int kRungs[] = {128, 192, 256, 384, 512, 768, 1024, 1536, 2048};

// A marble sphere of radius 0.3 (mm per unit as given) under a sun, seen from above.
struct SphereScene {
  explicit SphereScene(float mmPerUnit, bool lit = true) {
    scene.setMaterial(0, testing::marbleMaterial(mmPerUnit));
    scene.setMesh(1, sphere.desc({0, 0, 0}, 0.3f, 0));
    SsLightDesc sun = testing::sunLight(3.0f, 30.0f);
    scene.setLights(&sun, lit ? 1 : 0);
    scene.setCamera(testing::topDownCamera(0.5f));
    scene.resolveMaterials();
    translucent = scene.bounds(true);
  }
  testing::Sphere sphere{24, 12};
  Scene scene;
  Bounds translucent;
};

// The rule's texels follow its error model: kRuleTexels at kRuleError, and a target k times smaller
// needs k^(1 / kRulePower) times more.
TEST(AutoQuality, TargetErrorModelGivesTheFittedTexelsAndScalesWithItsPower) {
  EXPECT_DOUBLE_EQ(texelsAcrossFor(kRuleError), kRuleTexels);
  EXPECT_NEAR(texelsAcrossFor(kRuleError / 4.0), kRuleTexels * std::pow(4.0, 1.0 / kRulePower), 1e-9);
  EXPECT_NEAR(texelsAcrossFor(kRuleError * 4.0), kRuleTexels * std::pow(4.0, -1.0 / kRulePower), 1e-9);
  EXPECT_GT(kRuleEnergy, 0.0);
  EXPECT_LE(kRuleEnergy, 0.99);
}

TEST(AutoQuality, ResolutionIsTheSmallestRungWithEnoughTexelsPerRange) {
  SphereScene s(20.0f);
  double range = shortestRadius(s.scene, kRuleEnergy);
  ASSERT_GT(range, 0.0);
  EXPECT_LE(range, shortestRange(s.scene) * (1.0 + 1e-9)) << "R_P holds 95 % of the energy";
  int previous = 0;
  for (double target : {0.5, 0.1, 0.03, 0.01, 0.003, 0.001}) {
    int resolution = chooseResolution(s.scene, s.translucent, target, 16384, 0.0);
    EXPECT_NE(std::find(std::begin(kRungs), std::end(kRungs), resolution), std::end(kRungs)) << resolution;
    EXPECT_GE(resolution, previous) << "a smaller target never lowers the resolution";
    previous = resolution;
    double needed = texelsAcrossFor(target);
    auto texelsPerRange = [&](int r) { return range / lightTexel(s.scene, s.translucent, r, false); };
    if (resolution < kAutoResolutionMax) EXPECT_GE(texelsPerRange(resolution), needed * 0.999) << target;
    if (resolution > kAutoResolutionMin) {
      int below = *(std::find(std::begin(kRungs), std::end(kRungs), resolution) - 1);
      EXPECT_LT(texelsPerRange(below), needed) << target;
    }
  }
  bool reachable = false;
  chooseResolution(s.scene, s.translucent, 0.5, 16384, 0.0, &reachable);
  EXPECT_TRUE(reachable) << "a loose target is met";
  EXPECT_LE(chooseResolution(s.scene, s.translucent, 0.001, 256, 0.0), 256) << "the GPU's texture limit";
  SphereScene shorter(2000.0f);  // R_P a hundredth of the sphere's
  EXPECT_EQ(chooseResolution(shorter.scene, shorter.translucent, 0.001, 256, 0.0, &reachable), 256);
  EXPECT_FALSE(reachable) << "0.1 % needs more than 256 texels there";
  SphereScene tiny(1e6f);  // R_P a few thousandths of the largest buffer's texel
  EXPECT_EQ(chooseResolution(tiny.scene, tiny.translucent, 0.01, 16384, 0.0, &reachable), kAutoResolutionMax);
  EXPECT_FALSE(reachable) << "a range far below the largest buffer's texel is said unreachable";
  SphereScene dark(20.0f, false);
  EXPECT_EQ(chooseResolution(dark.scene, dark.translucent, 0.01, 16384, 0.0), kAutoResolutionMin) << "nothing lit";
}

TEST(AutoQuality, LevelsFollowTheScatteringRanges) {
  const int width = 256, height = 256, resolution = 512;
  SsSettings settings{};
  settings.alpha = 15.0f;
  int previousSplat = 0;
  for (float mmPerUnit : {2000.0f, 200.0f, 20.0f, 2.0f}) {  // R_P in scene units grows
    SphereScene s(mmPerUnit);
    Levels levels = chooseLevels(s.scene, settings, width, height, s.translucent, resolution, true, true);
    EXPECT_GE(levels.splat, previousSplat) << mmPerUnit;
    previousSplat = levels.splat;
    // The coarsest splatting level keeps kCoarsestPixelsPerRange pixels across the longest R_P;
    // one level coarser would not.
    double rangeMax = 0.0;
    for (double r : s.scene.denseMaterials()[0].kernel->effectiveRange()) rangeMax = std::max(rangeMax, r);
    double pixel = 1.0 / height;  // the camera sees 1 unit across
    double coarsest = pixel * double(1 << (levels.splat - 1));
    if (levels.splat > 1) EXPECT_GE(rangeMax / coarsest, kCoarsestPixelsPerRange) << mmPerUnit;
    if (levels.splat < 8) EXPECT_LT(rangeMax / (2.0 * coarsest), kCoarsestPixelsPerRange) << mmPerUnit;
    // Eq. 11: the coarsest irradiance level's texel, alpha times over, stays within R_P.
    double texel = lightTexel(s.scene, s.translucent, resolution, true) * double(1 << (levels.irradiance - 1));
    if (levels.irradiance > 1) EXPECT_LE(settings.alpha * texel, shortestRange(s.scene)) << mmPerUnit;
    if (levels.irradiance < 8) EXPECT_GT(settings.alpha * 2.0 * texel, shortestRange(s.scene)) << mmPerUnit;
    Levels brute = chooseLevels(s.scene, settings, width, height, s.translucent, resolution, false, false);
    EXPECT_EQ(brute.irradiance, 1);
    EXPECT_EQ(brute.splat, 1);
  }
  EXPECT_GT(previousSplat, 1) << "the longest range takes several splatting levels";

  SphereScene s(20.0f);
  settings.levels = 8;  // by hand: capped where the coarsest level keeps a texel / pixel
  Levels manual = chooseLevels(s.scene, settings, 256, 256, s.translucent, 192, true, true);
  EXPECT_EQ(manual.irradiance, 7) << "192 halves exactly down to 3 x 3";
  EXPECT_EQ(manual.splat, 8);
  Levels tiny = chooseLevels(s.scene, settings, 4, 2, s.translucent, 512, true, true);
  EXPECT_EQ(tiny.splat, 3) << "4 x 2 pixels: levels of 4, 2 and 1 pixels across";
}

}  // namespace
}  // namespace subsplat
