// Soft shadows (docs/SOFT_SHADOWS.md): the penumbra of a box on a floor under a sun with an angle
// and under a point light with a radius, FULL's percentage-closer soft shadows against REFERENCE's
// shadow rays to the light's disk, and against the penumbra's geometry.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class SoftShadow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
    SsMaterialDesc grey = testing::greyMaterial(0.5f);
    ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
    SsMeshDesc floor = quad.desc(4.0f, 0);
    ASSERT_EQ(ssSetMesh(context, 0, &floor), SS_OK);
    setBox();
    SsCameraDesc camera = testing::topDownCamera(2.0f);  // x in [-2, 2] over kSize pixels
    camera.world_to_view[12] = -1.0f;                     // looking at x = 1: the shadow's side
    ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  }
  void TearDown() override { ssReleaseContext(context); }

  // The row y = 0 (5 rows averaged), channel G.
  std::vector<double> row(int method, const SsLightDesc& light) {
    EXPECT_EQ(ssSetLights(context, &light, 1), SS_OK) << ssGetLastError();
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 512;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK);
    std::vector<float> rgba(size_t(kSize) * kSize * 4);
    EXPECT_EQ(ssRender(context, kSize, kSize, rgba.data()), SS_OK) << ssGetLastError();
    std::vector<double> out(kSize, 0.0);
    for (int x = 0; x < kSize; ++x)
      for (int y = kSize / 2 - 2; y < kSize / 2 + 3; ++y) out[size_t(x)] += rgba[(size_t(y) * kSize + x) * 4 + 1] / 5.0;
    return out;
  }
  // The 10-90 % width (scene units) of the shadow's far edge along the row y = 0: the row over
  // the same row without the box (the light's own fall-off divided out), from the box's side on.
  double penumbraWidth(int method, const SsLightDesc& light) {
    std::vector<double> shadowed = row(method, light);
    EXPECT_EQ(ssRemoveMesh(context, 1), SS_OK);
    std::vector<double> open = row(method, light);
    setBox();
    int start = int((0.5 + 1.0) / 4.0 * kSize) + 2;
    std::vector<double> visible(kSize, 1.0);
    for (int x = start; x < kSize; ++x) visible[size_t(x)] = open[size_t(x)] > 0.0 ? shadowed[size_t(x)] / open[size_t(x)] : 1.0;
    if (std::getenv("SOFT_SHADOW_ROWS"))
      for (int x = start; x < kSize; x += 2) std::printf("%d:%.3f%s", x, visible[size_t(x)], x + 2 >= kSize ? "\n" : " ");
    auto crossing = [&](double level) {
      for (int x = start; x + 1 < kSize; ++x)
        if (visible[size_t(x)] < level && visible[size_t(x + 1)] >= level)
          return x + (level - visible[size_t(x)]) / (visible[size_t(x + 1)] - visible[size_t(x)]);
      return double(kSize);
    };
    return (crossing(0.9) - crossing(0.1)) * 4.0 / kSize;
  }
  // The penumbra's width (penumbraWidth) in FULL and REFERENCE under `light`, and in FULL under the
  // same light made hard; printed after `what`.
  struct Widths {
    double full, reference, hard;
  };
  Widths widths(SsLightDesc light, const char* what) {
    Widths w{penumbraWidth(SS_METHOD_FULL, light), penumbraWidth(SS_METHOD_REFERENCE, light), 0.0};
    light.soft_size = 0.0f;
    w.hard = penumbraWidth(SS_METHOD_FULL, light);
    std::printf("%s penumbra 10-90 %%: FULL %.3f, REFERENCE %.3f, hard %.3f\n", what, w.full, w.reference, w.hard);
    return w;
  }
  // A sun at 45 degrees with a 10-degree disk.
  static SsLightDesc softSun() {
    SsLightDesc sun = testing::sunLight(3.0f, 45.0f);
    sun.soft_size = float(10.0 * M_PI / 180.0);
    return sun;
  }
  // A point light 3 units above the floor and 0.8 to the side of the box, radius 0.3.
  static SsLightDesc softPoint() {
    SsLightDesc point{};
    point.type = SS_LIGHT_POINT;
    point.color[0] = point.color[1] = point.color[2] = 1.0f;
    point.strength = 400.0f;
    point.position[0] = -0.8f, point.position[2] = 3.0f;
    point.soft_size = 0.3f;
    return point;
  }
  // A box of 1 x 1 x 1 on the floor, centred on the origin.
  void setBox() {
    SsMeshDesc mesh = box.desc(0);
    ASSERT_EQ(ssSetMesh(context, 1, &mesh), SS_OK);
  }
  static constexpr int kSize = 128;
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  testing::Box box{glm::vec3(-0.5f, -0.5f, 0.0f), glm::vec3(0.5f, 0.5f, 1.0f)};
};

// A sun at 45 degrees with a 10-degree disk: the far edge is cast by the box's top edge, 1.41
// units up the light's ray; the penumbra is 1.41 x 0.175 across the light, 0.35 along the floor
// (1 / cos 45), of which a disk's 10-90 % is about 0.63 (0.22).
TEST_F(SoftShadow, SunPenumbraMatchesReference) {
  Widths w = widths(softSun(), "sun (geometry: 0.35 wide)");
  EXPECT_NEAR(w.full / w.reference, 1.0, 0.15);
  EXPECT_GT(w.reference, 0.15);
  EXPECT_LT(w.reference, 0.35);
  EXPECT_LT(w.hard, 0.1);
}

// The point light: the shadow's far edge is inside the cube map's -z face (a percentage-closer
// filter does not cross faces).
TEST_F(SoftShadow, PointLightPenumbraMatchesReference) {
  Widths w = widths(softPoint(), "point");
  EXPECT_NEAR(w.full / w.reference, 1.0, 0.15);
  EXPECT_GT(w.reference, 0.1);
}

// The same box over a translucent floor (Skin1 at 100 mm a unit: its light spreads about 0.04
// units, well under the penumbra): the light entering the floor is shadowed softly, from the
// light's shape, as on an opaque floor (docs/SOFT_SHADOWS.md, "Translucent objects"). Before, the
// entries were the texels the light's centre sees, and the shadow on a translucent surface was
// hard whatever the light's size.
class TranslucentFloorSoftShadow : public SoftShadow {
 protected:
  void SetUp() override {
    SoftShadow::SetUp();
    SsMaterialDesc skin = testing::skinMaterial(100.0f);
    ASSERT_EQ(ssSetMaterial(context, 1, &skin), SS_OK) << ssGetLastError();
    SsMeshDesc floor = quad.desc(4.0f, 1);
    ASSERT_EQ(ssSetMesh(context, 0, &floor), SS_OK);
  }
};

TEST_F(TranslucentFloorSoftShadow, PointLightPenumbraMatchesReference) {
  Widths w = widths(softPoint(), "translucent floor, point");
  EXPECT_NEAR(w.full / w.reference, 1.0, 0.15);
  EXPECT_GT(w.reference, 0.1);
  EXPECT_LT(w.hard, 0.5 * w.reference);
}

TEST_F(TranslucentFloorSoftShadow, SunPenumbraMatchesReference) {
  Widths w = widths(softSun(), "translucent floor, sun");
  EXPECT_NEAR(w.full / w.reference, 1.0, 0.15);
  EXPECT_GT(w.reference, 0.15);
  EXPECT_LT(w.hard, 0.5 * w.reference);
}

// A translucent sphere beside an opaque box that hides none of the light from it, under a point
// light: with a radius, the light entering the sphere takes the soft-entry path (the box is another
// object: the irradiance buffer without it, every entry filtered on the map of every surface), and
// with nothing in the way that changes nothing: the sphere renders as under the same light without a
// radius, in FULL and in REFERENCE (which then traces past its own surfaces). Small and cheap: it
// runs under the sanitizers, where the penumbra tests above do not.
TEST(SoftEntries, NothingInTheWayLeavesTheLightEnteringUnchanged) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  SsMaterialDesc skin = testing::skinMaterial(20.0f), grey = testing::greyMaterial(0.5f);
  skin.specular = 0.0f;
  ASSERT_EQ(ssSetMaterial(context, 0, &skin), SS_OK);
  ASSERT_EQ(ssSetMaterial(context, 1, &grey), SS_OK);
  testing::Sphere sphere{32, 16};
  SsMeshDesc ball = sphere.desc(glm::vec3(0.0f), 0.5f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &ball), SS_OK);
  testing::Box box{glm::vec3(1.5f, -0.2f, -0.5f), glm::vec3(1.9f, 0.2f, -0.1f)};
  SsMeshDesc boxMesh = box.desc(1);
  ASSERT_EQ(ssSetMesh(context, 1, &boxMesh), SS_OK);
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsLightDesc point{};
  point.type = SS_LIGHT_POINT;
  point.color[0] = point.color[1] = point.color[2] = 1.0f;
  point.strength = 100.0f;
  point.position[0] = -1.0f, point.position[2] = 2.0f;
  constexpr int kSize = 32;
  auto render = [&](int method, float radius) {
    point.soft_size = radius;
    EXPECT_EQ(ssSetLights(context, &point, 1), SS_OK);
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 128;
    settings.reference_samples = 5000;
    settings.samples = 1;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK);
    std::vector<float> rgba(size_t(kSize) * kSize * 4);
    EXPECT_EQ(ssRender(context, kSize, kSize, rgba.data()), SS_OK) << ssGetLastError();
    return rgba;
  };
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    std::vector<float> soft = render(method, 0.3f), hard = render(method, 0.0f);
    double difference = 0.0, total = 0.0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        double u = ((x + 0.5) / kSize * 2.0 - 1.0), v = ((y + 0.5) / kSize * 2.0 - 1.0);
        if (u * u + v * v > 0.45 * 0.45) continue;  // the sphere's pixels, away from its outline
        for (int c = 0; c < 3; ++c) {
          size_t i = (size_t(y) * kSize + x) * 4 + size_t(c);
          difference += std::abs(double(soft[i]) - double(hard[i]));
          total += hard[i];
        }
      }
    std::printf("method %d: soft against hard on the sphere, mean difference %.2e of the mean\n", method,
                difference / total);
    EXPECT_GT(total, 0.0);
    EXPECT_LT(difference / total, 0.005) << "method " << method;
  }
  ssReleaseContext(context);
}

}  // namespace
}  // namespace subsplat

namespace subsplat {
namespace {

// Hard shadows on a map of their own (docs/SOFT_SHADOWS.md, "Shadow maps"): with an irradiance
// buffer of 64 texels in a 256-pixel image, the automatic shadow map's texels are no larger than
// the image's pixels (the sun's view spans the scene's bounding sphere, 11.4 units: 0.178 per
// texel at 64, against 4 / 256 = 0.0156 per pixel, so 64 x 11.4 = 727, up to 1024), and the
// shadow's staircase against REFERENCE's shadow rays shrinks with it.
TEST(ShadowMap, OwnResolutionFollowsTheImageNotTheIrradianceBuffer) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  SsMaterialDesc grey = testing::greyMaterial(0.5f);
  ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
  testing::Quad quad;
  SsMeshDesc floor = quad.desc(4.0f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &floor), SS_OK);
  // A box turned 30 degrees: its shadow's edges cross the map's texels at a slant (a staircase).
  testing::Box box{glm::vec3(-0.5f, -0.5f, 0.0f), glm::vec3(0.5f, 0.5f, 1.0f)};
  SsMeshDesc boxMesh = box.desc(0);
  glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), glm::vec3(0, 0, 1));
  std::memcpy(boxMesh.object_to_world, glm::value_ptr(turn), sizeof boxMesh.object_to_world);
  ASSERT_EQ(ssSetMesh(context, 1, &boxMesh), SS_OK);
  SsCameraDesc camera = testing::topDownCamera(2.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsLightDesc sun = testing::sunLight(3.0f, 45.0f);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  const int size = 256;
  auto render = [&](int method, int shadowResolution, int* used) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 64;
    settings.shadow_resolution = shadowResolution;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(size) * size * 4);
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    SsStats stats{};
    EXPECT_EQ(ssGetStats(context, &stats), SS_OK);
    if (used) *used = stats.shadow_resolution;
    return rgba;
  };
  std::vector<float> reference = render(SS_METHOD_REFERENCE, 0, nullptr);
  int coarseUsed = 0, automaticUsed = 0;
  std::vector<float> coarse = render(SS_METHOD_FULL, 64, &coarseUsed), automatic = render(SS_METHOD_FULL, 0, &automaticUsed);
  EXPECT_EQ(coarseUsed, 64);
  EXPECT_EQ(automaticUsed, 1024);
  // Pixels of the floor lit in one and shadowed in the other (green channel, half the lit value).
  auto wrong = [&](const std::vector<float>& image) {
    int count = 0;
    for (size_t i = 0; i < image.size() / 4; ++i)
      if ((image[4 * i + 1] > 0.2f) != (reference[4 * i + 1] > 0.2f)) ++count;
    return count;
  };
  int coarseWrong = wrong(coarse), automaticWrong = wrong(automatic);
  std::printf("pixels lit in one and shadowed in the other against REFERENCE: 64-texel map %d, %d-texel map %d\n",
              coarseWrong, automaticUsed, automaticWrong);
  if (!(automaticWrong * 5 < coarseWrong) || std::getenv("SHADOW_IMAGES")) {
    testing::writeComparison("shadow_map_automatic", automatic, reference, size, size);
    testing::writeComparison("shadow_map_64", coarse, reference, size, size);
  }
  EXPECT_LT(automaticWrong * 5, coarseWrong);
  ASSERT_EQ(ssReleaseContext(context), SS_OK);
}

}  // namespace
}  // namespace subsplat
