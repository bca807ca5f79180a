// A splatting budget per render (ssSetSplatBudget, docs/VIEWPORT.md, "Progressive splatting"): each
// render stays within it, the renders that follow go on where the last stopped, the refined image
// is the one-shot render's, and any change starts again.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

constexpr int kSize = 96;

uint64_t splatFragments(const SsStats& s) {  // the splat draws', without eq. 17's accumulation
  uint64_t sum = 0;
  for (int k = 0; k < s.splat_levels; ++k) sum += s.splat_level_fragments[k];
  return sum;
}

class ProgressiveSplatting : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
    // Skin on a sphere under a sun and a point light behind it: two light views, three levels.
    ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
    SsSettings settings = ssDefaultSettings();
    settings.method = SS_METHOD_FULL;
    settings.levels = 3;
    settings.irradiance_resolution = 128;
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  }
  void TearDown() override { ssReleaseContext(context); }
  SsStats render(std::vector<float>& rgba, int size = kSize) {
    rgba.assign(size_t(size) * size * 4, 0.0f);
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    return stats;
  }
  // The one-shot render (no budget) and its splatting fragments; skips where nothing is counted.
  uint64_t oneShot(std::vector<float>& rgba) {
    EXPECT_EQ(ssSetSplatBudget(context, 0), SS_OK);
    SsStats stats = render(rgba);
    EXPECT_EQ(stats.splatting_complete, 1);
    EXPECT_EQ(stats.splatting_progress, 1.0f);
    return stats.statistics_available ? splatFragments(stats) : 0;
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Sphere sphere;
};

// The budget is kept by a bound of each sample's fragments (pipeline/splatting.h, splat.geom): the
// fragments counted stay within it. A render may draw no fragment (it went through samples that
// draw none, charged for their vertex work), but it always advances.
TEST_F(ProgressiveSplatting, EachRenderStaysWithinItsBudgetAndAdvances) {
  std::vector<float> image;
  uint64_t whole = oneShot(image);
  if (whole == 0) GTEST_SKIP() << "this driver has no pipeline statistics queries";
  uint64_t budget = whole / 8;
  ASSERT_EQ(ssSetSplatBudget(context, budget), SS_OK);
  float progress = 0.0f;
  uint64_t spent = 0;
  int renders = 0;
  for (SsStats stats{}; !stats.splatting_complete && renders < 200; ++renders) {
    stats = render(image);
    uint64_t fragments = splatFragments(stats);
    std::printf("render %d: %llu splatting fragments of a budget of %llu, progress %.3f\n", renders + 1,
                (unsigned long long)fragments, (unsigned long long)budget, stats.splatting_progress);
    EXPECT_LE(fragments, budget) << "render " << renders + 1;
    EXPECT_GT(stats.splatting_progress, progress) << "render " << renders + 1 << " did not advance";
    progress = stats.splatting_progress;
    spent += fragments;
  }
  EXPECT_EQ(progress, 1.0f);
  EXPECT_GE(renders, 8) << "a budget of an eighth takes at least eight renders";
  EXPECT_EQ(spent, whole) << "every splat drawn once, over all the renders";
}

TEST_F(ProgressiveSplatting, TheRefinedImageIsTheOneShotRender) {
  std::vector<float> expected, image;
  uint64_t whole = oneShot(expected);
  if (whole == 0) GTEST_SKIP() << "this driver has no pipeline statistics queries";
  ASSERT_EQ(ssSetSplatBudget(context, whole / 5), SS_OK);
  SsStats first = render(image);
  ASSERT_EQ(first.splatting_complete, 0);
  double partialDifference = 0.0, scale = 0.0;
  for (size_t i = 0; i < image.size(); ++i) {
    partialDifference = std::max(partialDifference, double(std::abs(image[i] - expected[i])));
    scale = std::max(scale, double(std::abs(expected[i])));
  }
  EXPECT_GT(partialDifference, 1e-3 * scale) << "the first render shows part of the splats";
  for (int renders = 1; !render(image).splatting_complete; ++renders) ASSERT_LT(renders, 200);
  double difference = 0.0;
  for (size_t i = 0; i < image.size(); ++i)
    difference = std::max(difference, double(std::abs(image[i] - expected[i])));
  std::printf("largest difference %.3g of a largest value %.3g\n", difference, scale);
  EXPECT_LE(difference, 1e-4 * scale);
}

// With anti-aliasing's samples in the same render (final renders' way), the direct light is drawn
// again on every render; the refined image is still the one-shot render's.
TEST_F(ProgressiveSplatting, TheRefinedImageWithSamplesIsTheOneShotRender) {
  SsSettings settings{};
  ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
  settings.samples = 3;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  std::vector<float> expected, image;
  uint64_t whole = oneShot(expected);
  if (whole == 0) GTEST_SKIP() << "this driver has no pipeline statistics queries";
  ASSERT_EQ(ssSetSplatBudget(context, whole / 4), SS_OK);
  ASSERT_EQ(render(image).splatting_complete, 0);
  for (int renders = 1; !render(image).splatting_complete; ++renders) ASSERT_LT(renders, 200);
  double difference = 0.0, scale = 0.0;
  for (size_t i = 0; i < image.size(); ++i) {
    difference = std::max(difference, double(std::abs(image[i] - expected[i])));
    scale = std::max(scale, double(std::abs(expected[i])));
  }
  EXPECT_LE(difference, 1e-4 * scale);
}

TEST_F(ProgressiveSplatting, AnyChangeStartsAgainAndTheSameCameraGoesOn) {
  std::vector<float> image;
  uint64_t whole = oneShot(image);
  if (whole == 0) GTEST_SKIP() << "this driver has no pipeline statistics queries";
  ASSERT_EQ(ssSetSplatBudget(context, whole / 6), SS_OK);
  float first = render(image).splatting_progress;
  ASSERT_LT(first, 0.5f);
  SsCameraDesc camera = testing::topDownCamera(0.35f);  // the camera it has
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  EXPECT_GT(render(image).splatting_progress, first) << "the same camera again goes on";
  SsLightDesc sun = testing::sunLight(3.0f, 70.0f);
  auto restarted = [&](const char* what) {
    float progress = render(image).splatting_progress;
    EXPECT_NEAR(progress, first, 1e-6) << what << " must start the splatting again";
  };
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  first = render(image).splatting_progress;  // one light view now: its own first share
  render(image);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  restarted("the lights sent again");
  camera = testing::topDownCamera(0.4f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  first = render(image).splatting_progress;
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  EXPECT_GT(render(image).splatting_progress, first);
  SsMaterialDesc marble = testing::marbleMaterial(100.0f);
  ASSERT_EQ(ssSetMaterial(context, 0, &marble), SS_OK);
  first = render(image).splatting_progress;
  render(image);
  SsMaterialDesc same = marble;
  ASSERT_EQ(ssSetMaterial(context, 0, &same), SS_OK);
  restarted("a material sent again");
  render(image, kSize + 8);
  float other = render(image, kSize + 8).splatting_progress;
  EXPECT_GT(other, 0.0f);
  std::vector<float> back;
  render(back, kSize);
  EXPECT_NEAR(render(back, kSize).splatting_progress, other, 0.5f);  // sanity: it renders at the old size again
}

}  // namespace
}  // namespace subsplat
