// Area lights (reference/lighting.h; docs/AREA_LIGHTS.md): the polygon's irradiance against the
// closed forms for a square and a disk, and a Lambertian plane under a square light rendered by
// FULL and REFERENCE against the closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/lighting.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

// A light of `shape` at height h above the origin, facing down, radiance 1 (colour 1).
SsLightDesc areaLight(int shape, float size, float h) {
  SsLightDesc l{};
  l.type = SS_LIGHT_AREA;
  l.color[0] = l.color[1] = l.color[2] = 1.0f;
  l.position[2] = h;
  l.direction[2] = -1.0f;
  l.area_axis[0] = 1.0f;
  l.area_shape = shape;
  l.area_size[0] = l.area_size[1] = size;
  double area = shape == SS_AREA_DISK ? 0.25 * M_PI * size * size : double(size) * size;
  l.strength = float(4.0 * area);  // radiance P / (4 A) = 1
  return l;
}

// On the axis of a square of half-side a at height h, facing it: 4 corner rectangles of a x a.
double squareOnAxis(double a, double h) {
  double x = a / h, s = std::sqrt(1.0 + x * x);
  return 4.0 * M_PI * (1.0 / (2.0 * M_PI)) * 2.0 * (x / s) * std::atan(x / s);
}

TEST(AreaLight, PolygonIrradianceIsTheClosedFormsOnAxisAndNoneBehind) {
  for (float h : {0.25f, 1.0f, 4.0f}) {
    SsLightDesc square = areaLight(SS_AREA_SQUARE, 1.0f, h), disk = areaLight(SS_AREA_DISK, 1.0f, h);
    EXPECT_FLOAT_EQ(areaRadiance(square), 1.0f);
    glm::vec3 up(0, 0, 1), down(0, 0, -1), origin(0.0f);
    EXPECT_NEAR(polygonIrradiance(areaCorners(square), down, origin, up) / squareOnAxis(0.5, h), 1.0, 1e-4) << h;
    double diskExact = M_PI * 0.25 / (double(h) * h + 0.25);
    // The disk is a 16-gon of the same area: within 0.5 % on its axis.
    EXPECT_NEAR(polygonIrradiance(areaCorners(disk), down, origin, up) / diskExact, 1.0, 5e-3) << h;
    EXPECT_EQ(polygonIrradiance(areaCorners(square), down, glm::vec3(0, 0, 2 * h), up), 0.0f) << "behind";
  }
  // A surface facing sideways at the light's height sees none of it; tilted, part of it (clipped).
  SsLightDesc square = areaLight(SS_AREA_SQUARE, 1.0f, 1.0f);
  EXPECT_NEAR(polygonIrradiance(areaCorners(square), glm::vec3(0, 0, -1), glm::vec3(2, 0, 0.999f), glm::vec3(1, 0, 0)),
              0.0f, 1e-3f);
  float tilted = polygonIrradiance(areaCorners(square), glm::vec3(0, 0, -1), glm::vec3(0.3f, 0, 0),
                                   glm::normalize(glm::vec3(1, 0, 1)));
  float straight = polygonIrradiance(areaCorners(square), glm::vec3(0, 0, -1), glm::vec3(0.3f, 0, 0), glm::vec3(0, 0, 1));
  EXPECT_GT(tilted, 0.0f);
  EXPECT_LT(tilted, straight);
}

// A grey Lambertian plane under a square light 1 unit above it, seen from above: the centre's
// radiance is albedo / pi x the closed form, for FULL and REFERENCE.
TEST(AreaLightRender, LambertianPlaneUnderASquareLightIsTheClosedForm) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  SsMaterialDesc grey = testing::greyMaterial(0.5f);
  ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
  testing::Quad quad;
  SsMeshDesc plane = quad.desc(4.0f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &plane), SS_OK);
  SsCameraDesc camera = testing::topDownCamera(0.1f);  // the centre, where the closed form holds
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsLightDesc light = areaLight(SS_AREA_SQUARE, 1.0f, 1.0f);
  ASSERT_EQ(ssSetLights(context, &light, 1), SS_OK);
  double expected = 0.5 / M_PI * squareOnAxis(0.5, 1.0);
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 64;
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
    std::vector<float> rgba(8 * 8 * 4);
    ASSERT_EQ(ssRender(context, 8, 8, rgba.data()), SS_OK) << ssGetLastError();
    double mean = 0.0;
    for (int i = 0; i < 64; ++i) mean += rgba[size_t(i) * 4 + 1] / 64.0;
    EXPECT_NEAR(mean / expected, 1.0, 0.01) << "method " << method;
  }
  ssReleaseContext(context);
}

// A translucent slab (marble) under a square light: FULL's irradiance samples carry the polygon's
// irradiance, as REFERENCE's do: the two agree within 3 %.
TEST(AreaLightRender, TranslucentSlabUnderASquareLightAgreesWithReference) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::Quad quad;
  ASSERT_EQ(testing::setSlab(context, quad, testing::marbleMaterial(200.0f)), SS_OK) << ssGetLastError();
  SsLightDesc light = areaLight(SS_AREA_SQUARE, 1.0f, 1.0f);
  ASSERT_EQ(ssSetLights(context, &light, 1), SS_OK);
  double means[2] = {0.0, 0.0};
  int i = 0;
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 256;
    settings.reference_samples = 40000;
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
    std::vector<float> rgba(16 * 16 * 4);
    ASSERT_EQ(ssRender(context, 16, 16, rgba.data()), SS_OK) << ssGetLastError();
    for (int p = 0; p < 256; ++p) means[i] += rgba[size_t(p) * 4 + 1] / 256.0;
    ++i;
  }
  EXPECT_GT(means[1], 0.0);
  EXPECT_NEAR(means[0] / means[1], 1.0, 0.03) << "FULL " << means[0] << ", REFERENCE " << means[1];
  ssReleaseContext(context);
}

}  // namespace
}  // namespace subsplat
