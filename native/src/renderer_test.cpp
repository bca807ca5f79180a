// Whole frames through the C API in a surfaceless EGL context.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "material/dipole.h"
#include "material/splat_kernel.h"
#include "pipeline/auto_quality.h"
#include "renderer.h"
#include "scene.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

struct Frame {
  int width, height;
  std::vector<float> rgba;
  // Mean of channel c over the centred square covering `fraction` of each side.
  double centreMean(int c, double fraction) const {
    int x0 = int(width * (1 - fraction) / 2), x1 = width - x0;
    int y0 = int(height * (1 - fraction) / 2), y1 = height - y0;
    double sum = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) sum += rgba[(size_t(y) * width + x) * 4 + c];
    return sum / double((x1 - x0) * (y1 - y0));
  }
};

class Render : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  Frame render(int size) {
    Frame f{size, size, std::vector<float>(size_t(size) * size * 4)};
    EXPECT_EQ(ssRender(context, size, size, f.rgba.data()), SS_OK) << ssGetLastError();
    return f;
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
};

// The coverage figures, counted on the GPU, equal a count on the CPU of the
// image and the exitance pass: translucent pixels (the pass's alpha), those
// with a finite exitance whose sum is > 0, and non-finite pixels.
TEST_F(Render, CoverageStatsEqualACountOfTheImageAndTheExitancePass) {
  testing::Sphere sphere(48, 24);
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
  SsMaterialDesc opaque{};
  opaque.kind = SS_MATERIAL_OPAQUE;
  opaque.base_color[0] = opaque.base_color[1] = opaque.base_color[2] = 0.5f;
  opaque.roughness = 0.5f;
  ASSERT_EQ(ssSetMaterial(context, 1, &opaque), SS_OK) << ssGetLastError();
  SsMeshDesc card = quad.desc(0.1f, 1);  // an opaque card over part of the sphere
  card.object_to_world[12] = 0.2f, card.object_to_world[13] = 0.2f, card.object_to_world[14] = 0.5f;
  ASSERT_EQ(ssSetMesh(context, 1, &card), SS_OK) << ssGetLastError();
  const int size = 64;
  for (int method : {SS_METHOD_BRUTE, SS_METHOD_FULL}) {
    SsSettings settings{method, 256, {0, 0, 0, 0}};
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    Frame f = render(size);
    SsStats stats{};
    ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
    std::vector<float> exitance(f.rgba.size());
    ASSERT_EQ(ssGetPass(context, SS_PASS_EXITANCE, size, size, exitance.data()), SS_OK) << ssGetLastError();
    uint64_t translucent = 0, lit = 0, nonfinite = 0;
    for (size_t i = 0; i < f.rgba.size(); i += 4) {
      const float* out = &f.rgba[i];
      if (!std::isfinite(out[0]) || !std::isfinite(out[1]) || !std::isfinite(out[2]) || !std::isfinite(out[3]))
        ++nonfinite;
      const float* b = &exitance[i];
      if (b[3] != 1.0f) continue;
      ++translucent;
      if (std::isfinite(b[0]) && std::isfinite(b[1]) && std::isfinite(b[2]) && b[0] + b[1] + b[2] > 0.0f) ++lit;
    }
    EXPECT_EQ(stats.translucent_pixels, translucent) << method;
    EXPECT_EQ(stats.lit_translucent_pixels, lit) << method;
    EXPECT_EQ(stats.nonfinite_pixels, nonfinite) << method;
    EXPECT_GT(translucent, 0u);
    EXPECT_GT(lit, 0u);
    EXPECT_LT(translucent, uint64_t(size) * size) << "the card and the background are not translucent";
  }
}

// A wide slab of marble under a sun: far from the edges the radiant exitance
// is E * Rd_total (DESIGN.md), so the radiance seen from straight above is
// F_t(0) / pi * E_sun cos(theta) F_t(theta) * Rd_total.
TEST_F(Render, PlaneExitanceMatchesDipoleTotalReflectance) {
  const float mmPerUnit = 200.0f;  // support radius ~0.2 units, slab half-width 2
  SsMaterialDesc marble = testing::marbleMaterial(mmPerUnit);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  SsSettings settings = ssDefaultSettings();
  settings.method = SS_METHOD_BRUTE;
  settings.irradiance_resolution = 256;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  for (float incidence : {0.0f, 60.0f}) {
    SsLightDesc sun = testing::sunLight(3.0f, incidence);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    Frame frame = render(64);
    double cosTheta = std::cos(incidence * M_PI / 180.0);
    for (int c = 0; c < 3; ++c) {
      double rdTotal = Dipole({marble.sigma_a[c], marble.sigma_s_prime[c], marble.eta}).totalReflectance();
      double expected = fresnelTransmittance(marble.eta, 1.0) / M_PI * 3.0 * cosTheta *
                        fresnelTransmittance(marble.eta, cosTheta) * rdTotal;
      EXPECT_NEAR(frame.centreMean(c, 0.5) / expected, 1.0, 0.03)
          << "channel " << c << " incidence " << incidence;
    }
  }
  SsStats stats{};
  ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
  EXPECT_GT(stats.splat_count, 0u);
  EXPECT_EQ(stats.light_views, 1);
}

TEST_F(Render, OpaqueLambertianPlaneUnderSunIsAlbedoOverPiTimesIrradiance) {
  SsMaterialDesc grey{};
  grey.kind = SS_MATERIAL_OPAQUE;
  grey.base_color[0] = grey.base_color[1] = grey.base_color[2] = 0.5f;
  grey.roughness = 1.0f;
  ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
  SsMeshDesc plane = quad.desc(2.0f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &plane), SS_OK);
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsLightDesc sun = testing::sunLight(2.0f, 45.0f);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  Frame frame = render(32);
  EXPECT_NEAR(frame.centreMean(0, 0.8), 0.5 / M_PI * 2.0 * std::cos(M_PI / 4), 1e-4);
}

TEST_F(Render, BackgroundWhereNothingIsHit) {
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsSettings settings = ssDefaultSettings();
  settings.method = SS_METHOD_BRUTE;
  settings.irradiance_resolution = 64;
  const float background[4] = {0.1f, 0.2f, 0.3f, 1.0f};
  std::copy(background, background + 4, settings.background);
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  Frame frame = render(8);
  EXPECT_FLOAT_EQ(frame.rgba[2], 0.3f);
  EXPECT_FLOAT_EQ(frame.rgba[3], 1.0f);
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

class Adaptive : public Render {
 protected:
  SsStats renderWith(int method, int size, int levels = 3, int irradiance = 256, float alpha = 0.0f) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = irradiance;
    settings.levels = levels;
    settings.alpha = alpha;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    last = render(size);
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    return stats;
  }
  Frame last{0, 0, {}};
};

// The plane test holds for adaptive selection: coarse samples carry the flux
// of their children, so E * Rd_total is kept. A small alpha makes the coarse
// levels fine enough for the material; at 60 degrees the depth range keeps
// level 2 out (its texels span more than z0 along the light).
TEST_F(Adaptive, PlaneExitanceWithinThreePercentWithCoarseSamples) {
  SsMaterialDesc marble = testing::marbleMaterial(200.0f);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  for (float incidence : {0.0f, 60.0f}) {
    SsLightDesc sun = testing::sunLight(3.0f, incidence);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    SsStats brute = renderWith(SS_METHOD_BRUTE, 64);
    SsStats adaptive = renderWith(SS_METHOD_ADAPTIVE, 64, 3, 256, 0.1f);
    double cosTheta = std::cos(incidence * M_PI / 180.0);
    for (int c = 0; c < 3; ++c) {
      double rdTotal = Dipole({marble.sigma_a[c], marble.sigma_s_prime[c], marble.eta}).totalReflectance();
      double expected = fresnelTransmittance(marble.eta, 1.0) / M_PI * 3.0 * cosTheta *
                        fresnelTransmittance(marble.eta, cosTheta) * rdTotal;
      EXPECT_NEAR(last.centreMean(c, 0.5) / expected, 1.0, 0.03) << "channel " << c << " incidence " << incidence;
    }
    EXPECT_EQ(adaptive.levels, 3);
    std::printf("incidence %.0f: selected %llu %llu %llu, brute %llu\n", incidence,
                (unsigned long long)adaptive.selected_per_level[0], (unsigned long long)adaptive.selected_per_level[1],
                (unsigned long long)adaptive.selected_per_level[2], (unsigned long long)brute.selected_per_level[0]);
    EXPECT_GT(adaptive.selected_per_level[1] + adaptive.selected_per_level[2], adaptive.selected_per_level[0])
        << "incidence " << incidence;
    EXPECT_LT(adaptive.splat_count * 3, brute.splat_count) << "incidence " << incidence;
  }
}

uint64_t coveredTexels(const SsStats& s) {
  uint64_t covered = 0;
  for (int k = 0; k < 8; ++k) covered += s.selected_per_level[k] << (2 * k);
  return covered;
}

// Every translucent level-0 texel is covered by exactly one selected sample:
// the level-0 texels BRUTE splats equal the sum over levels of selected
// samples times the 4^k texels each covers. A sphere under a sun and a point
// light (six cube faces) has curvature, silhouettes and a terminator.
TEST_F(Adaptive, SelectionCoversEveryTexelExactlyOnce) {
  SsMaterialDesc marble = testing::marbleMaterial(25.0f);  // blue R_P 0.22: 0.7 x the radius
  testing::Sphere sphere;
  ASSERT_EQ(testing::setLitSphere(context, sphere, marble), SS_OK);
  SsStats brute = renderWith(SS_METHOD_BRUTE, 32);
  for (int levels : {2, 3, 5}) {
    SsStats adaptive = renderWith(SS_METHOD_ADAPTIVE, 32, levels);
    EXPECT_EQ(adaptive.levels, levels);
    std::printf("levels %d: selected %llu %llu %llu %llu %llu, brute %llu\n", levels,
                (unsigned long long)adaptive.selected_per_level[0], (unsigned long long)adaptive.selected_per_level[1],
                (unsigned long long)adaptive.selected_per_level[2], (unsigned long long)adaptive.selected_per_level[3],
                (unsigned long long)adaptive.selected_per_level[4], (unsigned long long)brute.selected_per_level[0]);
    EXPECT_EQ(coveredTexels(adaptive), brute.selected_per_level[0]) << levels << " levels";
    EXPECT_LT(adaptive.selected_per_level[0], brute.selected_per_level[0]) << levels << " levels";
    for (size_t i = 0; i < last.rgba.size(); ++i) ASSERT_TRUE(std::isfinite(last.rgba[i]));
  }
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

class Multires : public Render {
 protected:
  SsStats renderWith(int method, int size, float epsilon = 0.0f, int levels = 3) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 256;
    settings.levels = levels;
    settings.epsilon = epsilon;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    last = render(size);
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    return stats;
  }
  // The automatic-choice tests' scene: testing::setSlab's slab of `material` under a sun from
  // straight above.
  void setSlabUnderSun(const SsMaterialDesc& material) {
    ASSERT_EQ(testing::setSlab(context, quad, material), SS_OK) << ssGetLastError();
    SsLightDesc sun = testing::sunLight(3.0f, 0.0f);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  }
  Frame last{0, 0, {}};
};

// The plane test holds for multiresolution splatting and the full method:
// each distance lands in exactly one level, and eq. 17 gathers the levels.
TEST_F(Multires, PlaneExitanceWithinThreePercent) {
  SsMaterialDesc marble = testing::marbleMaterial(200.0f);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  for (int method : {SS_METHOD_MULTIRES, SS_METHOD_FULL}) {
    for (float incidence : {0.0f, 60.0f}) {
      SsLightDesc sun = testing::sunLight(3.0f, incidence);
      ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
      SsStats stats = renderWith(method, 128);
      EXPECT_EQ(stats.splat_levels, 3);
      EXPECT_EQ(stats.levels, method == SS_METHOD_FULL ? 3 : 1);
      double cosTheta = std::cos(incidence * M_PI / 180.0);
      for (int c = 0; c < 3; ++c) {
        double rdTotal = Dipole({marble.sigma_a[c], marble.sigma_s_prime[c], marble.eta}).totalReflectance();
        double expected = fresnelTransmittance(marble.eta, 1.0) / M_PI * 3.0 * cosTheta *
                          fresnelTransmittance(marble.eta, cosTheta) * rdTotal;
        double ratio = last.centreMean(c, 0.5) / expected;
        std::printf("method %d incidence %.0f channel %d: %.4f\n", method, incidence, c, ratio);
        EXPECT_NEAR(ratio, 1.0, 0.03) << "method " << method << " channel " << c << " incidence " << incidence;
      }
    }
  }
}

// levels = 0 chooses the hierarchies per frame: a longer scattering range
// (fewer millimetres per unit) gets more splatting levels, and a range too
// short for the irradiance buffer gets no irradiance hierarchy at all.
TEST_F(Multires, AutomaticLevelsFollowTheScatteringRange) {
  int previous = 0;
  for (float mmPerUnit : {2000.0f, 200.0f, 20.0f}) {
    ASSERT_NO_FATAL_FAILURE(setSlabUnderSun(testing::marbleMaterial(mmPerUnit)));
    SsStats stats = renderWith(SS_METHOD_FULL, 128, 0.0f, 0);
    std::printf("%.0f mm per unit: %d irradiance, %d splatting levels\n", mmPerUnit, stats.levels, stats.splat_levels);
    EXPECT_GE(stats.splat_levels, previous) << mmPerUnit;
    EXPECT_GE(stats.levels, 1);
    EXPECT_LE(stats.splat_levels, 8);
    previous = stats.splat_levels;
  }
  EXPECT_GT(previous, 1);
  SsMaterialDesc marble = testing::marbleMaterial(2000.0f);  // R_P far below a texel and a pixel
  ASSERT_EQ(ssSetMaterial(context, 0, &marble), SS_OK);
  SsStats stats = renderWith(SS_METHOD_FULL, 128, 0.0f, 0);
  EXPECT_EQ(stats.levels, 1);
  EXPECT_EQ(stats.splat_levels, 1);
}

// irradiance_resolution = 0 chooses the cheapest resolution that puts the texels per R_P the
// target error needs on the translucent objects: a shorter range (more millimetres per unit)
// or a smaller target gets a finer buffer, up to the largest rung; the stats say what was
// chosen. A fixed resolution is used as set, and its texels per R_P are reported too.
TEST_F(Multires, AutomaticResolutionFollowsTheRangeAndTheTarget) {
  auto renderAuto = [&](float targetError) {
    SsSettings settings = ssDefaultSettings();
    settings.method = SS_METHOD_FULL;
    settings.irradiance_resolution = 0;
    settings.target_error = targetError;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    last = render(32);
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    return stats;
  };
  int previous = 0, first = 0;
  for (float mmPerUnit : {200.0f, 2000.0f, 20000.0f}) {
    ASSERT_NO_FATAL_FAILURE(setSlabUnderSun(testing::marbleMaterial(mmPerUnit)));
    SsStats stats = renderAuto(0.0f);
    std::printf("%.0f mm per unit: %d², %.2f texels per R_P\n", mmPerUnit, stats.irradiance_resolution,
                stats.texels_per_range);
    EXPECT_GE(stats.irradiance_resolution, kAutoResolutionMin);
    EXPECT_LE(stats.irradiance_resolution, kAutoResolutionMax);
    EXPECT_GE(stats.irradiance_resolution, previous) << mmPerUnit;
    EXPECT_GT(stats.texels_per_range, 0.0f);  // the rule's own texels: AutoQuality.*
    if (stats.irradiance_resolution < kAutoResolutionMax) EXPECT_EQ(stats.target_reachable, 1) << mmPerUnit;
    if (first == 0) first = stats.irradiance_resolution;
    previous = stats.irradiance_resolution;
  }
  EXPECT_GT(previous, first) << "a range 100 times shorter needs a finer buffer";
  SsMaterialDesc marble = testing::marbleMaterial(2000.0f);
  ASSERT_EQ(ssSetMaterial(context, 0, &marble), SS_OK);
  int coarse = renderAuto(0.05f).irradiance_resolution, fine = renderAuto(0.002f).irradiance_resolution;
  EXPECT_GT(fine, coarse) << "a smaller target gets a finer buffer";
  EXPECT_LT(renderAuto(0.05f).texels_per_range, renderAuto(0.002f).texels_per_range);
  SsStats fixed = renderWith(SS_METHOD_FULL, 32, 0.0f, 0);  // 256² irradiance
  EXPECT_EQ(fixed.irradiance_resolution, 256);
  EXPECT_GT(fixed.texels_per_range, 0.0f);

  SsSettings bad = ssDefaultSettings();
  bad.method = SS_METHOD_FULL;
  bad.irradiance_resolution = 0;
  bad.target_error = 0.9f;
  EXPECT_EQ(ssSetSettings(context, &bad), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("target error"), std::string::npos) << ssGetLastError();
}

// The debug passes: the selection pass colours the irradiance level of the
// samples that land on visible surfaces, and the splatting levels' own
// exitances add up to more than the finest one alone (each takes its share of
// the distances).
TEST_F(Multires, DebugPassesShowLevelsAndSelection) {
  SsMaterialDesc marble = testing::marbleMaterial(200.0f);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  SsLightDesc sun = testing::sunLight(3.0f, 0.0f);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  const int size = 64;
  std::vector<float> pass(size_t(size) * size * 4);
  SsSettings plain = ssDefaultSettings();
  plain.method = SS_METHOD_FULL;
  plain.irradiance_resolution = 256;
  plain.levels = 3;
  plain.alpha = 0.1f;
  ASSERT_EQ(ssSetSettings(context, &plain), SS_OK);
  render(size);
  EXPECT_NE(ssGetPass(context, SS_PASS_SELECTION, size, size, pass.data()), SS_OK) << "not enabled";
  SsSettings debug = plain;
  debug.debug_passes = 1;
  ASSERT_EQ(ssSetSettings(context, &debug), SS_OK);
  render(size);
  ASSERT_EQ(ssGetPass(context, SS_PASS_SELECTION, size, size, pass.data()), SS_OK) << ssGetLastError();
  int coloured[3] = {0, 0, 0};  // red, green, blue: levels 0, 1, 2
  for (size_t i = 0; i < pass.size(); i += 4)
    for (int c = 0; c < 3; ++c) coloured[c] += pass[i + c] == 1.0f && pass[i + 3] == 1.0f;
  EXPECT_GT(coloured[2], 0) << "alpha 0.1 makes level 2 fine enough on the flat slab";
  double levelSum[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(ssGetPass(context, SS_PASS_LEVEL_EXITANCE + k, size, size, pass.data()), SS_OK) << ssGetLastError();
    for (size_t i = 0; i < pass.size(); i += 4) levelSum[k] += pass[i];
  }
  EXPECT_GT(levelSum[0], 0.0);
  EXPECT_GT(levelSum[1] + levelSum[2], 0.0) << "the coarse levels take the far distances";
  EXPECT_NE(ssGetPass(context, SS_PASS_LEVEL_EXITANCE + 3, size, size, pass.data()), SS_OK) << "only 3 levels";
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

// The splatting stage's figures split into its parts (the paper's Table 2):
// the levels' and the accumulation's fragments and times add up to the
// stage's. (A level may be empty: where R-bar saturates at 1 for two adjacent
// levels, the coarser one takes all of the tail beyond R_P.)
TEST_F(Multires, StatsSplitSplattingIntoLevelsAndAccumulation) {
  SsMaterialDesc marble = testing::marbleMaterial(50.0f);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  SsLightDesc sun = testing::sunLight(3.0f, 0.0f);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  renderWith(SS_METHOD_FULL, 128);  // the context's first frame: its timers may be left out (StageProfiler)
  SsStats stats = renderWith(SS_METHOD_FULL, 128);
  ASSERT_EQ(stats.splat_levels, 3);
  if (!stats.statistics_available) GTEST_SKIP() << "this driver has no pipeline statistics queries";
  ASSERT_TRUE(stats.timers_available) << "timer queries are core GL 3.3";
  uint64_t parts = stats.accumulation_fragments, coarse = 0;
  double partMs = stats.accumulation_ms + stats.selection_ms;
  std::printf("selection: %.2f ms, accumulation: %.2f ms\n", stats.selection_ms, stats.accumulation_ms);
  EXPECT_GT(stats.selection_ms, 0.0) << "Algorithm 1's list is made once per light view, and timed";
  for (int k = 0; k < stats.splat_levels; ++k) {
    std::printf("level %d: %llu fragments, %.2f ms\n", k, (unsigned long long)stats.splat_level_fragments[k],
                stats.splat_level_ms[k]);
    if (k > 0) coarse += stats.splat_level_fragments[k];
    parts += stats.splat_level_fragments[k];
    partMs += stats.splat_level_ms[k];
  }
  for (int k = stats.splat_levels; k < 8; ++k) EXPECT_EQ(stats.splat_level_fragments[k], 0u);
  EXPECT_GT(stats.splat_level_fragments[0], 0u);
  EXPECT_GT(coarse, 0u) << "the coarse levels take the far distances";
  EXPECT_GT(stats.accumulation_fragments, 0u);
  EXPECT_EQ(parts, stats.fragment_invocations[SS_STAGE_SPLATTING]);
  EXPECT_NEAR(partMs, stats.stage_ms[SS_STAGE_SPLATTING], 1e-6 * stats.stage_ms[SS_STAGE_SPLATTING] + 1e-9);
  SsStats brute = renderWith(SS_METHOD_BRUTE, 128);
  EXPECT_EQ(brute.accumulation_fragments, 0u) << "one level: nothing to gather";
  EXPECT_EQ(brute.splat_level_fragments[0], brute.fragment_invocations[SS_STAGE_SPLATTING]);
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

// Issue 21's wide-range case, in fragment invocations (not time): marble at 25 mm per unit on the
// slab, whose R_P is 0.13 of the slab's bounding radius and about 60 pixels here, the case the paper's method is for.
// FULL at the product's settings (automatic levels) against BRUTE at the same irradiance
// resolution. The goal is 5x; the bound is what FULL does today, so that it cannot slip
// back (docs/MULTIRES.md, "Where the time goes when the range is long", says what stops it).
TEST_F(Multires, FullDoesFewerFragmentsThanBruteWhereTheRangeIsLong) {
  constexpr int kSize = 160;  // pixels across the slab's unit square
  SsMaterialDesc marble = testing::marbleMaterial(25.0f);
  setSlabUnderSun(marble);
  SsProfileInfo info{};
  ASSERT_EQ(ssGetProfileInfo(&marble, &info), SS_OK);
  double longest = std::max({info.effective_range[0], info.effective_range[1], info.effective_range[2]});
  double radius = std::sqrt(2.0 * 2.0 * 2.0);  // the slab: a square of half-size 2, its bounding sphere
  ASSERT_GT(longest / radius, 0.1) << "the longest R_P above 0.1 of the bounding radius";
  renderWith(SS_METHOD_FULL, kSize, 0.0f, 0);  // the context's first frame (shaders, tables)
  SsStats brute = renderWith(SS_METHOD_BRUTE, kSize);
  SsStats full = renderWith(SS_METHOD_FULL, kSize, 0.0f, 0);
  if (!brute.statistics_available || !full.statistics_available)
    GTEST_SKIP() << "this driver has no pipeline statistics queries";
  double ratio = double(brute.fragment_invocations[SS_STAGE_SPLATTING]) /
                 double(std::max<uint64_t>(full.fragment_invocations[SS_STAGE_SPLATTING], 1));
  std::printf("longest R_P %.3f units (%.2f of the bounding radius, %.0f pixels); splatting fragments: BRUTE "
              "%llu, FULL %llu (%d levels): %.2fx fewer\n",
              longest, longest / radius, longest * kSize, (unsigned long long)brute.fragment_invocations[SS_STAGE_SPLATTING],
              (unsigned long long)full.fragment_invocations[SS_STAGE_SPLATTING], full.splat_levels, ratio);
  EXPECT_GE(ratio, 2.0);
}

}  // namespace
}  // namespace subsplat
