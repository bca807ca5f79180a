// The automatic resolution on scenes it was not calibrated on (issue 21; docs/AUTO.md, "Held-out
// scenes"). The error model was fitted on the calibration set of procedural scenes
// (bench/auto_fit.py); this runs the first scenes of the test set, disjoint from it by construction,
// at a small size (bench/auto_sets.sh runs the whole set).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pipeline/auto_quality.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

using testing::SceneSet;

// The two sets never share a scene: a scene's seed carries its set in its top bit, so no index of
// one set draws a seed of the other; the scenes themselves differ too.
TEST(AutoQualityHeldOut, TheCalibrationAndTestSetsAreDisjointByConstruction) {
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(testing::sceneSeed(SceneSet::Calibration, i) >> 63, 0u);
    EXPECT_EQ(testing::sceneSeed(SceneSet::Test, i) >> 63, 1u);
  }
  std::vector<std::string> calibration, test;
  for (int i = 0; i < 64; ++i) {
    calibration.push_back(testing::proceduralScene(SceneSet::Calibration, i, 64, 48).description);
    test.push_back(testing::proceduralScene(SceneSet::Test, i, 64, 48).description);
  }
  int same = 0;
  for (const std::string& c : calibration) same += int(std::count(test.begin(), test.end(), c));
  EXPECT_EQ(same, 0) << "a test scene is described as a calibration scene";
  // A scene is a function of its set and index alone.
  EXPECT_EQ(testing::proceduralScene(SceneSet::Test, 3, 64, 48).description,
            testing::proceduralScene(SceneSet::Test, 3, 64, 48).description);
}

// On the first two test scenes (bench/auto_sets.sh: all 24, at 120 x 90), at the resolution AUTO chooses: the error that resolution adds over a
// converged buffer's (MULTIRES at it against MULTIRES at testing::referenceResolution, relative RMSE,
// shadow maps fixed) is within what the error model fitted on the calibration set predicts
// (testing::kModel*: the model generalises to scenes it was not fitted on), and the render reports
// whether the target is reachable, at the largest buffer when it is not. Whether AUTO's rule meets
// its 1 % target is printed, not asserted: on the held-out set it does not (docs/AUTO.md, "Held-out
// scenes").
TEST(AutoQualityHeldOut, TheCalibratedErrorModelBoundsTheErrorOnTestScenes) {
  constexpr int kScenes = 2, kWidth = 64, kHeight = 48;  // 39 s on CI's 2 cores
  constexpr float kTarget = 0.01f;
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  int withinTarget = 0;
  for (int index = 0; index < kScenes; ++index) {
    testing::ProceduralScene scene = testing::proceduralScene(SceneSet::Test, index, kWidth, kHeight);
    ASSERT_EQ(scene.apply(context), SS_OK) << ssGetLastError();
    std::vector<float> automatic, chosen, finest;
    SsStats autoStats{}, stats{};
    ASSERT_EQ(testing::renderAt(context, SS_METHOD_FULL, kWidth, kHeight, 0, kTarget, automatic, autoStats), SS_OK)
        << ssGetLastError();
    int resolution = autoStats.irradiance_resolution;
    if (!autoStats.target_reachable) EXPECT_EQ(resolution, kAutoResolutionMax) << "an unreachable target renders at the largest buffer";
    int reference = testing::referenceResolution(resolution, autoStats.texels_per_range);
    if (reference <= resolution) {  // AUTO at the largest buffer: nothing finer to measure against
      std::printf("test scene %d: %s: AUTO %d%s, not measured\n", index, scene.description.c_str(), resolution,
                  autoStats.target_reachable ? "" : " (said unreachable)");
      continue;
    }
    ASSERT_EQ(testing::renderAt(context, SS_METHOD_MULTIRES, kWidth, kHeight, resolution, kTarget, chosen, stats), SS_OK)
        << ssGetLastError();
    ASSERT_EQ(testing::renderAt(context, SS_METHOD_MULTIRES, kWidth, kHeight, reference, kTarget, finest, stats), SS_OK)
        << ssGetLastError();
    double added = testing::relativeRmse(chosen, finest);
    // The model's texels: the coarsest light texel (from R_P and its texels) across max(R, pixels).
    double texel = testing::shortestRadius(scene, 0.95) / autoStats.texels_per_range;
    double length = std::max(testing::shortestRadius(scene, testing::kModelEnergy), testing::kModelPixels * scene.pixel);
    double predicted = testing::kModelError * std::pow(length / texel, -testing::kModelPower);
    withinTarget += added <= kTarget;
    std::printf("test scene %d: %s: AUTO %d%s, %.3f model texels; adds %.4f over %d, the model predicts at most %.4f%s\n",
                index, scene.description.c_str(), resolution, autoStats.target_reachable ? "" : " (said unreachable)",
                length / texel, added, reference, predicted, added <= kTarget ? "" : "; above the 1 % target");
    if (added > predicted)
      ADD_FAILURE() << "test scene " << index << " (" << scene.description << "): " << resolution << " adds " << added
                    << " over " << reference << ", above the calibrated model's " << predicted << "; images: "
                    << testing::writeComparison("auto_heldout_" + std::to_string(index), chosen, finest, kWidth, kHeight);
  }
  std::printf("%d of %d test scenes within the 1 %% target at AUTO's resolution\n", withinTarget, kScenes);
  ssReleaseContext(context);
}

}  // namespace
}  // namespace subsplat
