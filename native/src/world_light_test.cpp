// The world light (world_light.h; docs/WORLD.md): its directions' weights, a Lambertian plane
// and a translucent half-space under a uniform world against the exact answers, and occlusion
// by an object, for the GPU methods and REFERENCE.
#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"
#include "transport/hfunction.h"
#include "world_light.h"

namespace subsplat {
namespace {

// An unoccluded surface of any normal gets exactly pi L from the world's directions together.
TEST(WorldDirections, WeighAnUnoccludedSurfaceToPiForEveryNormal) {
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  for (int count : {6, 8, 16, 64}) {
    std::vector<glm::vec3> directions = worldDirections(count);
    ASSERT_EQ(directions.size(), size_t(count));
    for (const glm::vec3& w : directions) EXPECT_NEAR(glm::length(w), 1.0f, 1e-5f);
    for (int i = 0; i < 1000; ++i) {
      glm::vec3 n = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
      float sum = 0.0f;
      for (const glm::vec3& w : directions) sum += std::max(glm::dot(n, w), 0.0f) * worldWeight(directions, n);
      EXPECT_NEAR(sum, float(M_PI), 1e-4f) << count << " directions";
    }
  }
}

// The automatic choice follows the world's share of the light at the objects.
TEST(WorldDirections, AutomaticCountFollowsTheWorldsShare) {
  Bounds fit;
  fit.extend(glm::vec3(-1.0f)), fit.extend(glm::vec3(1.0f));
  SsLightDesc world{}, sun = testing::sunLight(1.0f, 0.0f);
  world.type = SS_LIGHT_WORLD;
  world.color[0] = world.color[1] = world.color[2] = 1.0f;
  for (auto [worldRadiance, expected] : {std::pair{0.01f, -1}, {0.1f, 8}, {1.0f, 16}}) {
    world.strength = worldRadiance;  // pi L against the sun's 1 W/m^2: 3 %, 24 %, 76 %
    world.world_below[0] = world.world_below[1] = world.world_below[2] = worldRadiance;
    EXPECT_EQ(automaticWorldDirections({world, sun}, fit), expected) << worldRadiance;
  }
  EXPECT_EQ(automaticWorldDirections({world}, fit), 16);
}

class World : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  void setWorld(const glm::vec3& radiance, int directions) {
    SsLightDesc world{};
    world.type = SS_LIGHT_WORLD;
    for (int c = 0; c < 3; ++c) world.color[c] = world.world_below[c] = radiance[c];
    world.strength = 1.0f;
    world.world_directions = directions;
    ASSERT_EQ(ssSetLights(context, &world, 1), SS_OK) << ssGetLastError();
  }
  std::vector<float> render(int method, int size, int resolution = 128) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = resolution;
    settings.reference_samples = 20000;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(size) * size * 4);
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    return rgba;
  }
  // Mean of channel c over the pixels [x0, x1) x [y0, y1) of a size x size image.
  static double mean(const std::vector<float>& rgba, int size, int c, int x0, int x1, int y0, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) sum += rgba[(size_t(y) * size + x) * 4 + c];
    return sum / double((x1 - x0) * (y1 - y0));
  }
  // A grey plane (albedo 0.5) under `world`, seen from above and from below, unshadowed and in 16
  // directions, FULL and REFERENCE: its radiance within 2 % of expected(facing) (+1 from above).
  void expectEachSide(SsLightDesc world, const std::function<double(float)>& expected, const std::string& what) {
    SsMaterialDesc plane = testing::greyMaterial(0.5f);
    ASSERT_EQ(ssSetMaterial(context, 0, &plane), SS_OK);
    SsMeshDesc mesh = quad.desc(2.0f, 0);
    ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK);
    for (float facing : {1.0f, -1.0f}) {  // the camera above looking down, or below looking up
      SsCameraDesc camera = testing::topDownCamera(1.0f);
      glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 5 * facing), glm::vec3(0), glm::vec3(0, 1, 0));
      std::memcpy(camera.world_to_view, glm::value_ptr(view), sizeof camera.world_to_view);
      ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
      for (int directions : {-1, 16}) {
        world.world_directions = directions;
        ASSERT_EQ(ssSetLights(context, &world, 1), SS_OK);
        for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
          std::vector<float> image = render(method, 16);
          EXPECT_NEAR(mean(image, 16, 1, 2, 14, 2, 14) / expected(facing), 1.0, 0.02)
              << what << (facing > 0 ? ", from above" : ", from below") << ", " << directions
              << " directions, method " << method;
        }
      }
    }
  }
  // A closed box from lo to hi, outward winding.
  void setBox(uint32_t id, const glm::vec3& lo, const glm::vec3& hi, uint32_t material) {
    box = std::make_unique<testing::Box>(lo, hi);
    SsMeshDesc mesh = box->desc(material);
    ASSERT_EQ(ssSetMesh(context, id, &mesh), SS_OK) << ssGetLastError();
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  std::unique_ptr<testing::Box> box;
};

// The test: radiance = albedo x world radiance within 2 %, with the world shadowed in 8
// and 16 directions and unshadowed, for FULL and REFERENCE.
TEST_F(World, LambertianPlaneUnderAUniformWorldIsAlbedoTimesRadiance) {
  SsMaterialDesc plane = testing::greyMaterial(0.5f);
  ASSERT_EQ(ssSetMaterial(context, 0, &plane), SS_OK);
  SsMeshDesc mesh = quad.desc(2.0f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK);
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  const glm::vec3 radiance(0.2f, 0.5f, 1.0f);
  for (int directions : {-1, 8, 16}) {
    setWorld(radiance, directions);
    for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
      std::vector<float> image = render(method, 16);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(mean(image, 16, c, 2, 14, 2, 14) / (0.5 * radiance[c]), 1.0, 0.02)
            << directions << " directions, method " << method << ", channel " << c;
    }
  }
}

// A world of two halves (an environment map's means above and below its horizon): a surface facing
// up gets pi L_above, one facing down pi L_below, a wall the mean; drawn in directions and unshadowed.
TEST_F(World, AWorldOfTwoHalvesLightsEachSideWithItsOwn) {
  SsLightDesc world{};
  world.type = SS_LIGHT_WORLD;
  world.color[0] = world.color[1] = world.color[2] = 1.0f;
  world.strength = 0.8f;
  world.world_below[0] = world.world_below[1] = world.world_below[2] = 0.2f;
  expectEachSide(world, [](float facing) { return 0.5 * (facing > 0.0f ? 0.8 : 0.2); }, "two halves");
}

// A world given as spherical harmonics (API 17: an environment map's light after its suns),
// L(w) = a + b w_z + c w_x: a surface facing up gets pi a + 2 pi b / 3 (the cosine lobe keeps 2/3 of
// a linear term), one facing down pi a - 2 pi b / 3, whatever c; drawn unshadowed and in 16
// directions, FULL and REFERENCE. With b = c = 0 it is the uniform world a.
TEST_F(World, HarmonicsLightEachSideWithTheirIrradiance) {
  const float a = 0.5f;
  for (std::pair<float, float> bc : {std::pair{0.0f, 0.0f}, std::pair{0.3f, 0.4f}}) {
    const float b = bc.first, c = bc.second;  // not a structured binding: C++17 lambdas cannot capture those
    SsLightDesc world{};
    world.type = SS_LIGHT_WORLD;
    for (int channel = 0; channel < 3; ++channel) {
      world.world_sh[0 + channel] = a * 3.5449077f;  // a / Y_00
      world.world_sh[6 + channel] = b * 2.0466534f;  // b / (Y_10 / z)
      world.world_sh[9 + channel] = c * 2.0466534f;  // c / (Y_11 / x)
    }
    expectEachSide(world, [&](float facing) { return 0.5 * (a + facing * 2.0 * b / 3.0); },
                   "harmonics b " + std::to_string(b) + ", c " + std::to_string(c));
  }
}

// An opaque box on a grey floor under a world shadowed in 16 directions: the floor beside the box
// sees less of the world than the floor far from it, and FULL agrees with REFERENCE (ray-traced
// shadows of the same directions) there. Unshadowed, the floor is the same everywhere.
TEST_F(World, AnObjectShadowsTheFloorBesideIt) {
  SsMaterialDesc floor = testing::greyMaterial(0.5f);
  ASSERT_EQ(ssSetMaterial(context, 0, &floor), SS_OK);
  SsMeshDesc mesh = quad.desc(2.0f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK);
  setBox(1, glm::vec3(-0.25f, -0.25f, 0.0f), glm::vec3(0.25f, 0.25f, 0.5f), 0);
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  const int size = 32;  // 1/16 unit per pixel: the box covers pixels 12..19
  auto besideAndFar = [&](const std::vector<float>& image) {
    // Beside: a strip 0.125 units wide along the box's +x side; far: the image's +x edge.
    return std::pair{mean(image, size, 1, 20, 22, 12, 20), mean(image, size, 1, 30, 32, 12, 20)};
  };
  setWorld(glm::vec3(1.0f), 16);
  auto [fullBeside, fullFar] = besideAndFar(render(SS_METHOD_FULL, size));
  auto [refBeside, refFar] = besideAndFar(render(SS_METHOD_REFERENCE, size));
  std::printf("floor beside the box / far from it: FULL %.3f / %.3f, REFERENCE %.3f / %.3f\n", fullBeside, fullFar,
              refBeside, refFar);
  EXPECT_LT(fullBeside, 0.9 * fullFar);
  EXPECT_LT(refBeside, 0.9 * refFar);
  EXPECT_NEAR(fullBeside / refBeside, 1.0, 0.05);
  EXPECT_NEAR(fullFar / refFar, 1.0, 0.02);
  setWorld(glm::vec3(1.0f), -1);
  auto [ambientBeside, ambientFar] = besideAndFar(render(SS_METHOD_FULL, size));
  EXPECT_NEAR(ambientBeside / ambientFar, 1.0, 1e-3);
  EXPECT_NEAR(ambientFar / 0.5, 1.0, 0.02);
}

// A translucent half-space (a box 40 mean free paths thick, index matched, TABULATED) under a
// uniform world, seen from straight above, against the exact L (1 - sqrt(1 - a) H(1)): exact
// when unshadowed; with 16 shadowed directions the angular factors are summed over the 8
// directions above the surface instead of integrated: 0.9-2.3 % over, bounded at 4 %.
TEST_F(World, TranslucentHalfSpaceUnderAUniformWorld) {
  SsMaterialDesc m = testing::skinMaterial(20.0f);
  m.eta = 1.0f;
  m.specular = 0.0f;
  m.profile_model = SS_PROFILE_TABULATED;
  ASSERT_EQ(ssSetMaterial(context, 0, &m), SS_OK);
  setBox(0, glm::vec3(-2.0f, -2.0f, -3.0f), glm::vec3(2.0f, 2.0f, 0.0f), 0);
  SsCameraDesc camera = testing::topDownCamera(0.5f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  const glm::vec3 radiance(1.0f, 0.5f, 0.25f);
  for (int directions : {-1, 16}) {
    setWorld(radiance, directions);
    for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
      std::vector<float> image = render(method, 16, 256);
      for (int c = 0; c < 3; ++c) {
        double a = m.sigma_s_prime[c] / (m.sigma_a[c] + m.sigma_s_prime[c]);
        double exact = radiance[c] * (1.0 - std::sqrt(1.0 - a) * HFunction(a)(1.0));
        double ratio = mean(image, 16, c, 4, 12, 4, 12) / exact;
        std::printf("%d directions, method %d, channel %d: %.4f of the exact radiance\n", directions, method, c,
                    ratio);
        EXPECT_NEAR(ratio, 1.0, directions < 0 ? 0.01 : 0.04);
      }
    }
  }
}

}  // namespace
}  // namespace subsplat
