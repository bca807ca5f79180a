// Anti-aliasing (docs/ANTIALIASING.md): the pixel filter's samples, edges that take intermediate
// values, more samples closer to many, the first sample's exitance carried to the others at the
// cost of little, and REFERENCE's samples where the GPU methods take theirs.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"
#include "util/pixel_filter.h"

namespace subsplat {
namespace {

// Sample 0 is the pixel's centre; the offsets follow Blackman-Harris on each axis: within its
// support, centred, with its variance (numerically: the variance of the normalised window).
TEST(PixelFilter, OffsetsFollowBlackmanHarrisAndStartAtTheCentre) {
  EXPECT_EQ(pixelFilterOffset(0, 1.5f), glm::vec2(0.0f));
  const float width = 1.5f;
  double expected = 0.0, norm = 0.0;
  for (int i = 0; i < 20000; ++i) {
    double x = -width + 2.0 * width * (i + 0.5) / 20000.0;
    expected += x * x * blackmanHarris(x, width), norm += blackmanHarris(x, width);
  }
  expected /= norm;
  const int n = 4096;
  glm::dvec2 mean(0.0), square(0.0);
  for (int i = 0; i < n; ++i) {
    glm::vec2 o = pixelFilterOffset(i, width);
    ASSERT_LE(std::abs(o.x), width);
    ASSERT_LE(std::abs(o.y), width);
    mean += glm::dvec2(o) / double(n), square += glm::dvec2(o * o) / double(n);
  }
  EXPECT_NEAR(mean.x, 0.0, 0.01);
  EXPECT_NEAR(mean.y, 0.0, 0.01);
  EXPECT_NEAR(square.x / expected, 1.0, 0.02);
  EXPECT_NEAR(square.y / expected, 1.0, 0.02);
  EXPECT_NEAR(blackmanHarrisCdf(0.0, width), 0.5, 1e-12);
  EXPECT_NEAR(blackmanHarrisCdf(width, width), 1.0, 1e-12);
}

class AntiAliasing : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }

  // A grey square turned 20 degrees in the image, lit from above, on a black background.
  void setTiltedSquare() {
    SsMaterialDesc grey = testing::greyMaterial(0.8f);
    ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
    SsMeshDesc square = quad.desc(0.6f, 0);
    glm::mat4 m = glm::rotate(glm::mat4(1.0f), glm::radians(20.0f), glm::vec3(0, 0, 1)) *
                  glm::scale(glm::mat4(1.0f), glm::vec3(0.6f, 0.6f, 1.0f));
    std::memcpy(square.object_to_world, glm::value_ptr(m), sizeof square.object_to_world);
    ASSERT_EQ(ssSetMesh(context, 0, &square), SS_OK) << ssGetLastError();
    SsCameraDesc camera = testing::topDownCamera(1.0f);
    ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
    SsLightDesc sun = testing::sunLight(3.0f, 0.0f);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  }
  // A translucent sphere under a sun (testing::setLitSphere without its point light: one light
  // view, which the samples after the first need not render again).
  void setSunlitSphere() {
    ASSERT_EQ(testing::setLitSphere(context, sphere, testing::marbleMaterial(20.0f)), SS_OK) << ssGetLastError();
    SsLightDesc sun = testing::sunLight(3.0f, 70.0f);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    resolution = 64;
  }
  std::vector<float> render(int method, int samples, int firstSample = 0) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = resolution;
    settings.samples = samples;
    settings.first_sample = firstSample;
    settings.reference_samples = 20000;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(kSize) * kSize * 4);
    EXPECT_EQ(ssRender(context, kSize, kSize, rgba.data()), SS_OK) << ssGetLastError();
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    EXPECT_EQ(stats.samples, samples);
    return rgba;
  }
  // Pixels strictly between the background and the square's own value (green channel).
  static int intermediate(const std::vector<float>& rgba, float full) {
    int count = 0;
    for (size_t i = 0; i < rgba.size() / 4; ++i) {
      float g = rgba[4 * i + 1];
      if (g > 0.1f * full && g < 0.9f * full) ++count;
    }
    return count;
  }
  // A floor (material 0) and a box on it (boxMaterial; material 1 when translucent), an opaque post
  // when asked, seen from above, under a soft sun and a soft point light: the scene of the two tests
  // below. Returns the largest difference of a channel between a frame of n samples and the mean of
  // the n samples rendered one by one (first_sample = k), over the pixels `counted` accepts (x, y in
  // the scene's units), and checks that the samples after the first drew no shadow map.
  double samplesAgainstAlone(int n, bool translucentBox, bool post, const std::function<bool(double, double)>& counted,
                             const char* name) {
    SsMaterialDesc grey = testing::greyMaterial(0.6f), skin = testing::skinMaterial(50.0f);
    EXPECT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
    EXPECT_EQ(ssSetMaterial(context, 1, &skin), SS_OK);
    SsMeshDesc floor = quad.desc(2.0f, 0);
    EXPECT_EQ(ssSetMesh(context, 0, &floor), SS_OK);
    testing::Box box{glm::vec3(-0.3f, -0.3f, 0.0f), glm::vec3(0.3f, 0.3f, 0.6f)};
    SsMeshDesc boxMesh = box.desc(translucentBox ? 1 : 0);
    EXPECT_EQ(ssSetMesh(context, 1, &boxMesh), SS_OK);
    testing::Box postBox{glm::vec3(0.5f, -0.9f, 0.0f), glm::vec3(0.7f, -0.7f, 0.8f)};
    SsMeshDesc postMesh = postBox.desc(0);
    if (post) EXPECT_EQ(ssSetMesh(context, 2, &postMesh), SS_OK);
    SsCameraDesc camera = testing::topDownCamera(1.5f);
    EXPECT_EQ(ssSetCamera(context, &camera), SS_OK);
    SsLightDesc lights[2] = {testing::sunLight(2.0f, 40.0f), {}};
    lights[0].soft_size = 0.05f;
    lights[1].type = SS_LIGHT_POINT;
    lights[1].color[0] = lights[1].color[1] = lights[1].color[2] = 1.0f;
    lights[1].strength = 30.0f;
    lights[1].position[0] = 1.0f, lights[1].position[2] = 1.5f;
    lights[1].soft_size = 0.1f;
    EXPECT_EQ(ssSetLights(context, lights, 2), SS_OK) << ssGetLastError();
    std::vector<float> together = render(SS_METHOD_FULL, n), alone(together.size(), 0.0f);
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    EXPECT_EQ(stats.light_views, 7) << "the samples after the first draw no shadow map";
    for (int k = 0; k < n; ++k) {
      std::vector<float> one = render(SS_METHOD_FULL, 1, k);
      for (size_t i = 0; i < one.size(); ++i) alone[i] += one[i] / float(n);
    }
    double worst = 0.0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        if (!counted(((x + 0.5) / kSize * 2.0 - 1.0) * 1.5, ((y + 0.5) / kSize * 2.0 - 1.0) * 1.5)) continue;
        for (int c = 0; c < 4; ++c) {
          size_t i = (size_t(y) * kSize + x) * 4 + size_t(c);
          worst = std::max(worst, double(std::abs(together[i] - alone[i])));
        }
      }
    if (!(worst < 1e-4)) testing::writeComparison(name, together, alone, kSize, kSize);
    return worst;
  }

  // RMSE of the colour channels.
  static double rmse(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i)
      if (i % 4 != 3) sum += double(a[i] - b[i]) * double(a[i] - b[i]), ++n;
    return std::sqrt(sum / double(n));
  }

  static constexpr int kSize = 64;
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  testing::Sphere sphere{48, 24};
  int resolution = 128;
};

// One sample per pixel: every pixel is the square's or the background's. Eight: the pixels along
// the square's edges take values between, in FULL and in REFERENCE alike, and their alpha too.
TEST_F(AntiAliasing, PixelsAlongATiltedEdgeTakeIntermediateValues) {
  setTiltedSquare();
  const float full = 0.8f / float(M_PI) * 3.0f;  // albedo / pi x irradiance
  // The square's outline crosses about 4 x 0.6 x 2 x 32 / 1 = 154 pixel rows and columns.
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    std::vector<float> one = render(method, 1), eight = render(method, 8);
    EXPECT_EQ(intermediate(one, full), 0) << "method " << method;
    EXPECT_GT(intermediate(eight, full), 100) << "method " << method;
    int partial = 0;
    for (size_t i = 0; i < eight.size() / 4; ++i)
      if (eight[4 * i + 3] > 0.05f && eight[4 * i + 3] < 0.95f) ++partial;
    EXPECT_GT(partial, 100) << "alpha, method " << method;
  }
}

// Against a render of 256 samples, eight samples are much closer than one, for an opaque edge
// and for a translucent sphere (the first sample's exitance carried to the others).
TEST_F(AntiAliasing, EightSamplesAreCloserToTwoHundredFiftySixThanOne) {
  setTiltedSquare();
  std::vector<float> many = render(SS_METHOD_FULL, 256);
  double e1 = rmse(render(SS_METHOD_FULL, 1), many), e8 = rmse(render(SS_METHOD_FULL, 8), many);
  std::printf("tilted square: RMSE against 256 samples, 1 sample %.4f, 8 samples %.4f\n", e1, e8);
  if (!(e8 < 0.5 * e1)) testing::writeComparison("antialiasing_square_8", render(SS_METHOD_FULL, 8), many, kSize, kSize);
  EXPECT_LT(e8, 0.5 * e1);

  ASSERT_EQ(ssRemoveMesh(context, 0), SS_OK);
  setSunlitSphere();
  many = render(SS_METHOD_FULL, 256);
  e1 = rmse(render(SS_METHOD_FULL, 1), many), e8 = rmse(render(SS_METHOD_FULL, 8), many);
  std::printf("translucent sphere: RMSE against 256 samples, 1 sample %.4f, 8 samples %.4f\n", e1, e8);
  if (!(e8 < 0.5 * e1) || std::getenv("AA_IMAGES")) {
    testing::writeComparison("antialiasing_sphere_8", render(SS_METHOD_FULL, 8), many, kSize, kSize);
    testing::writeComparison("antialiasing_sphere_1", render(SS_METHOD_FULL, 1), many, kSize, kSize);
  }
  EXPECT_LT(e8, 0.5 * e1);
}

// The samples after the first are not splatted: they take the first's exitance at their own
// surface points. Against the mean of the same samples each splatted in its own render
// (first_sample = k), the difference is a small fraction of the image's mean.
TEST_F(AntiAliasing, CarriedExitanceAgreesWithSplattingEverySample) {
  setSunlitSphere();
  const int n = 7;
  std::vector<float> carried = render(SS_METHOD_FULL, n), splatted(carried.size(), 0.0f);
  for (int k = 0; k < n; ++k) {
    std::vector<float> one = render(SS_METHOD_FULL, 1, k);
    for (size_t i = 0; i < one.size(); ++i) splatted[i] += one[i] / float(n);
  }
  double mean = 0.0;
  for (size_t i = 0; i < splatted.size(); ++i)
    if (i % 4 != 3) mean += splatted[i] / double(splatted.size() * 3 / 4);
  double relative = rmse(carried, splatted) / mean;
  std::printf("carried against splatted per sample: RMSE %.4f of the mean\n", relative);
  if (!(relative < 0.01)) testing::writeComparison("antialiasing_carried", carried, splatted, kSize, kSize);
  EXPECT_LT(relative, 0.01);
}

// Opaque surfaces carry nothing from the first sample: a frame of n samples is the mean of the n
// samples rendered one by one (first_sample = k), to float rounding, with the shadow maps of every
// light view (a point light's six, a sun's) kept from the first sample and soft shadows.
TEST_F(AntiAliasing, OpaqueSamplesAreTheMeanOfTheSamplesRenderedAlone) {
  double worst = samplesAgainstAlone(5, false, false, [](double, double) { return true; }, "antialiasing_opaque");
  EXPECT_LT(worst, 1e-4) << "largest difference of a channel";
}

// The same with the box translucent and an opaque post beside it (docs/SOFT_SHADOWS.md,
// "Translucent objects"): the soft lights' irradiance buffers hold the box alone, their maps of
// every surface (the post's shadows) are drawn apart, and the samples after the first read copies
// of those too. On the floor, outside the box (whose pixels carry the first sample's exitance),
// the frame is the mean of the samples rendered alone.
TEST_F(AntiAliasing, OpaqueSamplesBesideATranslucentObjectAreTheMeanOfTheSamplesRenderedAlone) {
  // Outside the box and the pixels its edge touches.
  auto floor = [](double x, double y) { return std::abs(x) >= 0.45 || std::abs(y) >= 0.45; };
  double worst = samplesAgainstAlone(3, true, true, floor, "antialiasing_beside_translucent");
  EXPECT_LT(worst, 1e-4) << "largest difference of a channel on the floor";
}

// The GPU methods and REFERENCE look through the same jittered points: eight samples of each
// agree along the edge as one sample of each does in the interior.
TEST_F(AntiAliasing, ReferenceTakesItsSamplesWhereTheGpuMethodsDo) {
  setTiltedSquare();
  std::vector<float> gpu = render(SS_METHOD_FULL, 8), reference = render(SS_METHOD_REFERENCE, 8);
  double worst = 0.0;
  for (size_t i = 0; i < gpu.size(); ++i) worst = std::max(worst, double(std::abs(gpu[i] - reference[i])));
  if (!(worst < 0.01)) testing::writeComparison("antialiasing_gpu_reference", gpu, reference, kSize, kSize);
  EXPECT_LT(worst, 0.01) << "largest difference of a channel";
}

// Settings outside their ranges are refused, naming the field.
TEST_F(AntiAliasing, SettingsOutOfRangeAreRefused) {
  SsSettings settings = ssDefaultSettings();
  settings.samples = 1025;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("samples"), std::string::npos) << ssGetLastError();
  settings = ssDefaultSettings();
  settings.filter_width = 0.001f;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("filter width"), std::string::npos) << ssGetLastError();
  settings.filter_width = NAN;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  settings = ssDefaultSettings();
  settings.first_sample = -1;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("first sample"), std::string::npos) << ssGetLastError();
  settings = ssDefaultSettings();
  settings.samples = 0;
  settings.filter_width = 0.0f;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  SsSettings got{};
  ASSERT_EQ(ssGetSettings(context, &got), SS_OK);
  EXPECT_EQ(got.samples, 1);
  EXPECT_FLOAT_EQ(got.filter_width, 1.5f);
}

}  // namespace
}  // namespace subsplat
