// REFERENCE, the ruler: the analytic plane within 1 %, convergence as the
// sample count grows, determinism, cancel, and the exitance pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <cmath>
#include <vector>

#include "material/dipole.h"
#include "reference/ray_scene.h"
#include "reference/reference_renderer.h"
#include "scene.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class Reference : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  std::vector<float> render(int width, int height, uint32_t samples, SsStatus expected = SS_OK) {
    SsSettings settings = ssDefaultSettings();
    settings.method = SS_METHOD_REFERENCE;
    settings.irradiance_resolution = 256;
    settings.reference_samples = samples;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(width) * height * 4);
    EXPECT_EQ(ssRender(context, width, height, rgba.data()), expected) << ssGetLastError();
    return rgba;
  }
  // A marble sphere over nothing, lit by a sun from the side and a point
  // light behind: shadow terminators, curvature and thin-ish regions.
  void sphereScene() {
    SsMaterialDesc marble = testing::marbleMaterial(100.0f);
    ASSERT_EQ(testing::setLitSphere(context, sphere, marble), SS_OK);
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  testing::Sphere sphere;
};

double centreMean(const std::vector<float>& rgba, int size, int c, double fraction) {
  int x0 = int(size * (1 - fraction) / 2), x1 = size - x0;
  double sum = 0;
  for (int y = x0; y < x1; ++y)
    for (int x = x0; x < x1; ++x) sum += rgba[(size_t(y) * size + x) * 4 + c];
  return sum / double((x1 - x0) * (x1 - x0));
}

// Relative RMSE of rgb over pixels where the reference is lit.
double relativeRmse(const std::vector<float>& image, const std::vector<float>& reference) {
  double error = 0, norm = 0;
  for (size_t i = 0; i < image.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      double d = image[i + c] - reference[i + c];
      error += d * d;
      norm += double(reference[i + c]) * reference[i + c];
    }
  return std::sqrt(error / norm);
}

// DESIGN.md's analytic plane: exitance E Rd_total, seen from above as
// F_t(0)/pi E cos(theta) F_t(theta) Rd_total. The ruler must be within 1 %.
TEST_F(Reference, PlaneExitanceWithinOnePercentOfDipoleTotalReflectance) {
  SsMaterialDesc marble = testing::marbleMaterial(200.0f);
  ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
  for (float incidence : {0.0f, 60.0f}) {
    SsLightDesc sun = testing::sunLight(3.0f, incidence);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    std::vector<float> rgba = render(24, 24, 50000);
    double cosTheta = std::cos(incidence * M_PI / 180.0);
    for (int c = 0; c < 3; ++c) {
      double rdTotal = Dipole({marble.sigma_a[c], marble.sigma_s_prime[c], marble.eta}).totalReflectance();
      double expected = fresnelTransmittance(marble.eta, 1.0) / M_PI * 3.0 * cosTheta *
                        fresnelTransmittance(marble.eta, cosTheta) * rdTotal;
      double ratio = centreMean(rgba, 24, c, 0.5) / expected;
      std::printf("incidence %.0f channel %d: REFERENCE / analytic %.5f\n", incidence, c, ratio);
      EXPECT_NEAR(ratio, 1.0, 0.01)
          << "channel " << c << " incidence " << incidence;
    }
  }
}

// The same plane where the profile is far shorter than a sample's cell (a 4 m and a 40 m slab of
// marble, 2000 samples: cells about 0.1 units across, the support 0.01 and 0.001 units): every
// cell whose area reaches within the support of x_o counts, not only those whose centre does.
// Until stop 50 the search asked for the centre, and such a plane was speckled with black pixels,
// or black (the held-out calibration tori of docs/PRECOMPUTED.md, 9 m and 4 m, were 45-49 % off).
// Every pixel of the centre within 2 % of the analytic value, their mean within 1 %.
TEST_F(Reference, PlaneUnderAProfileShorterThanACellIsWholeEverywhere) {
  for (float mmPerUnit : {2000.0f, 20000.0f}) {
    SsMaterialDesc marble = testing::marbleMaterial(mmPerUnit);
    ASSERT_EQ(testing::setSlab(context, quad, marble), SS_OK);
    SsLightDesc sun = testing::sunLight(3.0f, 0.0f);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    const int size = 24;
    std::vector<float> rgba = render(size, size, 2000);
    for (int c = 0; c < 3; ++c) {
      double rdTotal = Dipole({marble.sigma_a[c], marble.sigma_s_prime[c], marble.eta}).totalReflectance();
      double expected = fresnelTransmittance(marble.eta, 1.0) / M_PI * 3.0 * fresnelTransmittance(marble.eta, 1.0) * rdTotal;
      double lowest = INFINITY, highest = 0.0;
      for (int y = size / 4; y < size - size / 4; ++y)
        for (int x = size / 4; x < size - size / 4; ++x) {
          double v = rgba[(size_t(y) * size + size_t(x)) * 4 + size_t(c)] / expected;
          lowest = std::min(lowest, v), highest = std::max(highest, v);
        }
      double ratio = centreMean(rgba, size, c, 0.5) / expected;
      std::printf("%.0f mm a unit, channel %d: REFERENCE / analytic %.5f, pixels %.4f-%.4f\n", double(mmPerUnit), c,
                  ratio, lowest, highest);
      EXPECT_NEAR(ratio, 1.0, 0.01) << mmPerUnit << " mm a unit, channel " << c;
      EXPECT_GT(lowest, 0.98) << mmPerUnit << " mm a unit, channel " << c;
      EXPECT_LT(highest, 1.02) << mmPerUnit << " mm a unit, channel " << c;
    }
  }
}

// Error against an 8x denser reference falls with every doubling of samples.
TEST_F(Reference, ConvergesAsSamplesIncrease) {
  sphereScene();
  const int size = 32;
  std::vector<float> truth = render(size, size, 320000);
  double previous = 1e30;
  for (uint32_t samples : {5000u, 10000u, 20000u, 40000u}) {
    double error = relativeRmse(render(size, size, samples), truth);
    std::printf("samples %u: relative RMSE %.5f\n", samples, error);
    EXPECT_LT(error, previous) << samples << " samples";
    previous = error;
  }
  EXPECT_LT(previous, 0.01);
}

TEST_F(Reference, SameSceneSameImage) {
  sphereScene();
  std::vector<float> a = render(32, 32, 20000), b = render(32, 32, 20000);
  EXPECT_EQ(a, b);
}

int32_t cancelAtOnce(float, void* calls) {
  ++*static_cast<int*>(calls);
  return 1;
}

TEST_F(Reference, ProgressCallbackCancelsPromptlyAndTheContextStaysUsable) {
  sphereScene();
  int calls = 0;
  ASSERT_EQ(ssSetProgressCallback(context, cancelAtOnce, &calls), SS_OK);
  auto start = std::chrono::steady_clock::now();
  render(400, 400, 4000000, SS_CANCELLED);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(calls, 1);
  std::printf("cancelled after %.2f s\n", seconds);
  ASSERT_EQ(ssSetProgressCallback(context, nullptr, nullptr), SS_OK);
  std::vector<float> rgba = render(16, 16, 5000);
  float pass[16 * 16 * 4];
  EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, 16, 16, pass), SS_OK) << ssGetLastError();
}

TEST_F(Reference, ExitancePassMarksTranslucentPixelsAndHoldsB) {
  sphereScene();
  const int size = 32;
  std::vector<float> rgba = render(size, size, 20000);
  std::vector<float> pass(rgba.size());
  ASSERT_EQ(ssGetPass(context, SS_PASS_EXITANCE, size, size, pass.data()), SS_OK) << ssGetLastError();
  EXPECT_NE(ssGetPass(context, SS_PASS_EXITANCE, size + 1, size, pass.data()), SS_OK);
  EXPECT_NE(ssGetPass(context, 7, size, size, pass.data()), SS_OK);
  int translucent = 0;
  for (size_t i = 0; i < pass.size(); i += 4) {
    bool hit = rgba[i + 3] > 0.0f;  // the sphere is the only object
    EXPECT_EQ(pass[i + 3], hit ? 1.0f : 0.0f);
    translucent += hit;
  }
  EXPECT_GT(translucent, size * size / 2);
  SsStats stats{};
  ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
  EXPECT_EQ(stats.translucent_pixels, uint64_t(translucent));
  EXPECT_GE(stats.splat_count, 20000u * 9 / 10);
  EXPECT_GT(stats.kernel_evaluations, 0u);
}

TEST_F(Reference, PassAndProgressCallsValidateTheirArguments) {
  float pixel[4];
  EXPECT_EQ(ssGetPass(nullptr, SS_PASS_EXITANCE, 1, 1, pixel), SS_INVALID_HANDLE);
  EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, 1, 1, pixel), SS_INVALID_ARGUMENT);  // nothing rendered yet
  EXPECT_EQ(ssSetProgressCallback(nullptr, cancelAtOnce, nullptr), SS_INVALID_HANDLE);
  sphereScene();
  render(4, 4, 1000);
  EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, 4, 4, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("NULL"), std::string::npos) << ssGetLastError();
}

TEST_F(Reference, RejectsOutOfRangeSampleCounts) {
  for (uint32_t samples : {1u, 999u, 100000001u}) {
    SsSettings settings = ssDefaultSettings();
    settings.method = SS_METHOD_REFERENCE;
    settings.irradiance_resolution = 256;
    settings.reference_samples = samples;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT) << samples;
  }
}

// The TABULATED model's forward shift on a curved part (docs/TRANSPORT.md, "The entry's forward
// shift"): the reflected light is centred on the surface, not on the entry's tangent plane, which
// over a sphere of radius R lies s^2 / 2R above it. Skin1 at 2 mm per unit on a sphere of 0.5 units
// (1 mm: about one red mean free path), a sun at 60 degrees: every shifted centre of a lit cell
// lies on the sphere's mesh, where the tangent plane's point was off it by up to s^2 / 2R.
TEST(ReferenceShift, TheShiftedCentreLiesOnTheSurface) {
  testing::Sphere sphere(96, 48);
  SsMaterialDesc skin = testing::skinMaterial(2.0f);
  skin.profile_model = SS_PROFILE_TABULATED;
  Scene scene;
  scene.setMaterial(0, skin);
  const float radius = 0.5f;
  scene.setMesh(0, sphere.desc(glm::vec3(0.0f), radius, 0));
  SsLightDesc sun = testing::sunLight(3.0f, 60.0f);
  scene.setLights(&sun, 1);
  scene.resolveMaterials();
  RayScene rays(scene);
  EnteringLight onto(scene, rays, true);
  const WorldMesh& wm = rays.meshes()[0];
  // The mesh's own sagitta: a flat facet of the 96 x 48 sphere lies up to R (1 - cos(pi / 48)) inside it.
  const float sagitta = radius * (1.0f - std::cos(float(M_PI) / 48.0f));
  double worstOff = 0.0, worstTangent = 0.0;
  int lit = 0;
  for (uint32_t t = 0; t < uint32_t(wm.indices->size() / 3); t += 7) {
    const glm::uvec3 v = wm.triangle(t);
    const glm::vec3 p = (wm.positions[v.x] + wm.positions[v.y] + wm.positions[v.z]) / 3.0f;
    glm::vec3 ng = glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x]);
    if (!(glm::length(ng) > 0.0f)) continue;
    ng = glm::normalize(ng);
    const glm::vec3 ns = glm::normalize(wm.normals[v.x] + wm.normals[v.y] + wm.normals[v.z]);
    const uint32_t base = (*wm.materials)[t];
    const Entering in = onto.at(0, t, p, ng, ns, 1e-4f, base, base, glm::vec2(0.0f));
    if (in.flux.g <= 0.0f) continue;
    for (int c = 0; c < 3; ++c) {
      const float s = glm::length(in.shift[c]);
      if (!(s > 0.05f * radius)) continue;  // too short for the curvature to tell
      ++lit;
      // The shift's tangent-plane point would be |p + tangent| - R ~ s^2 / 2R off the sphere.
      worstTangent = std::max(worstTangent, double(s * s / (2.0f * radius)));
      worstOff = std::max(worstOff, double(std::abs(glm::length(p + in.shift[c]) - radius)));
    }
  }
  std::printf("%d shifted centres: off the sphere by at most %.5f units (the tangent plane's point: up to %.5f; "
              "the mesh's sagitta %.5f)\n", lit, worstOff, worstTangent, double(sagitta));
  ASSERT_GT(lit, 100);
  EXPECT_LT(worstOff, 1.5 * sagitta + 1e-5);
  EXPECT_GT(worstTangent, 4.0 * sagitta) << "the scene should tell the tangent plane from the surface";
}

}  // namespace
}  // namespace subsplat
