// The TABULATED profile model end to end (material/transport_model.h; docs/TRANSPORT.md, "The
// TABULATED model"): a sun over a slab against the exact half-space radiance, light through thin
// slabs against adding-doubling, and the GPU methods against REFERENCE, which evaluates the same
// model on the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "material/transport_model.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"
#include "transport/adding_doubling.h"
#include "transport/hfunction.h"

namespace subsplat {
namespace {

struct Image {
  int size = 0;
  std::vector<float> rgba;
  double centreMean(int c, double fraction) const {
    int lo = int(size * (1 - fraction) / 2), hi = size - lo;
    double sum = 0;
    for (int y = lo; y < hi; ++y)
      for (int x = lo; x < hi; ++x) sum += rgba[(size_t(y) * size + x) * 4 + c];
    return sum / double((hi - lo) * (hi - lo));
  }
};

// Skin1 (Jensen et al. 2001) and Marble, index matched, no specular: the twin's scenes.
SsMaterialDesc medium(bool skin, float mmPerUnit) {
  SsMaterialDesc m = skin ? testing::skinMaterial(mmPerUnit) : testing::marbleMaterial(mmPerUnit);
  m.eta = 1.0f;
  m.specular = 0.0f;
  m.profile_model = SS_PROFILE_TABULATED;
  return m;
}

double albedo(const SsMaterialDesc& m, int c) { return m.sigma_s_prime[c] / (m.sigma_a[c] + m.sigma_s_prime[c]); }

class Tabulated : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  Image render(int method, int size, int resolution = 256) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = resolution;
    settings.reference_samples = 40000;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    Image image{size, std::vector<float>(size_t(size) * size * 4)};
    EXPECT_EQ(ssRender(context, size, size, image.rgba.data()), SS_OK) << ssGetLastError();
    return image;
  }
  // A box of half-size 2 x 2 and the given thickness (scene units), its top face at z = 0.
  void setBox(const SsMaterialDesc& material, float thickness) {
    const float h = 2.0f, z0 = -thickness, z1 = 0.0f;
    positions = {-h, -h, z1, h, -h, z1, h, h, z1, -h, h, z1, -h, -h, z0, h, -h, z0, h, h, z0, -h, h, z0};
    // Outward winding: top, bottom, four sides.
    indices = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1, 1, 5, 6, 1, 6, 2,
               2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0};
    SsMeshDesc mesh{};
    mesh.positions = positions.data();
    mesh.vertex_count = 8;
    mesh.indices = indices.data();
    mesh.triangle_count = 12;
    for (int i = 0; i < 4; ++i) mesh.object_to_world[i * 5] = 1.0f;
    ASSERT_EQ(ssSetMaterial(context, 0, &material), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK) << ssGetLastError();
    SsCameraDesc camera = testing::topDownCamera(0.5f);
    ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  }
  // The box of setBox lit from straight below by a sun of strength 3, seen from above: the slab's
  // scattered transmission 3 T(tau, 1, 1) of material m, by adding-doubling, per channel.
  void expectSlabTransmission(const Image& image, const SsMaterialDesc& m, float thickness, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
      double t = thickness * 20.0 * (m.sigma_a[c] + m.sigma_s_prime[c]);
      SlabSolution s = solveSlabByAddingDoubling(albedo(m, c), t, 1.0);
      double exact = 3.0 * s.transmittedRadiance.back();  // the node nearest mu = 1
      EXPECT_NEAR(image.centreMean(c, 0.5) / exact, 1.0, 0.03) << what << ", channel " << c;
    }
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  std::vector<float> positions;
  std::vector<uint32_t> indices;
};

// A sun of strength S at mu0 over a half-space seen from straight above: a S mu0 H(mu0) H(1) /
// (4 pi (mu0 + 1)) (Chandrasekhar), which the dipole misses by 5-40 %.
TEST_F(Tabulated, SlabUnderASunIsTheExactHalfSpaceRadiance) {
  for (bool skin : {true, false}) {
    SsMaterialDesc m = medium(skin, skin ? 20.0f : 100.0f);
    ASSERT_EQ(testing::setSlab(context, quad, m), SS_OK);
    for (float incidence : {0.0f, 60.0f}) {
      SsLightDesc sun = testing::sunLight(3.0f, incidence);
      ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
      double mu0 = std::cos(incidence * M_PI / 180.0);
      for (int method : {SS_METHOD_BRUTE, SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
        Image image = render(method, 24);
        for (int c = 0; c < 3; ++c) {
          HFunction h(albedo(m, c));
          double exact = 3.0 * mu0 * halfSpaceReflectedRadiance(h, mu0, 1.0);
          EXPECT_NEAR(image.centreMean(c, 0.5) / exact, 1.0, 0.01)
              << (skin ? "Skin1" : "Marble") << " channel " << c << " at " << incidence << " degrees, method " << method;
        }
      }
    }
  }
}

// A box of tau reduced mean free paths lit from straight below, seen from above: the slab's
// scattered transmission T(tau, 1, 1) times the irradiance, by adding-doubling.
TEST_F(Tabulated, LightThroughAThinSlabIsTheSlabsTransmission) {
  SsMaterialDesc m = medium(true, 20.0f);
  double sigmaT = m.sigma_a[1] + m.sigma_s_prime[1];  // per mm, green
  for (double tau : {0.5, 2.0}) {
    float thickness = float(tau / sigmaT / 20.0);  // scene units
    setBox(m, thickness);
    SsLightDesc sun = testing::sunLight(3.0f, 180.0f);  // from below
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    for (int method : {SS_METHOD_BRUTE, SS_METHOD_FULL, SS_METHOD_REFERENCE})
      expectSlabTransmission(render(method, 16), m, thickness,
                             "tau " + std::to_string(tau) + ", method " + std::to_string(method));
  }
}

// MATERIAL_EDIT (docs/MATERIAL_EDIT.md, "An edit"): the transport and the light through thin parts
// precomputed for the slab with twice the absorption, then the slab's own material as an edit,
// which draws no light view: the light through is evaluated again from what each view kept of it
// before the slab's transmission, and is the edited slab's T(tau, 1, 1), as above.
TEST_F(Tabulated, AnEditsLightThroughAThinSlabIsTheEditedSlabsTransmission) {
  SsMaterialDesc m = medium(true, 20.0f);
  SsMaterialDesc absorbing = m;
  for (float& a : absorbing.sigma_a) a *= 2.0f;
  double sigmaT = m.sigma_a[1] + m.sigma_s_prime[1];  // per mm, green
  for (double tau : {0.5, 2.0}) {
    float thickness = float(tau / sigmaT / 20.0);  // scene units
    setBox(absorbing, thickness);
    SsLightDesc sun = testing::sunLight(3.0f, 180.0f);  // from below
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    render(SS_METHOD_MATERIAL_EDIT, 16);
    ASSERT_EQ(ssSetMaterial(context, 0, &m), SS_OK);
    Image image = render(SS_METHOD_MATERIAL_EDIT, 16);
    SsStats stats{};
    ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
    EXPECT_EQ(stats.transport_reused, 1);
    EXPECT_EQ(stats.light_views, 0) << "the edit drew the light views again";
    expectSlabTransmission(image, m, thickness, "tau " + std::to_string(tau) + ", the edit");
  }
}

// The same slab lit from below at 60 degrees: the light crosses 2 x the thickness, and the slab
// transmits S mu0 T(tau, mu0, 1) of a slab tau thick (the table's slabs are in normal thickness).
// Within 5 %: mu0 = 0.5 lies between the table's cosines, where T is interpolated (within 7 % of
// adding-doubling there: TabulatedModel.ThinSlabsAreAddingDoublings); measured 4.5 % at most.
TEST_F(Tabulated, ObliqueLightThroughAThinSlabIsTheSlabsTransmission) {
  SsMaterialDesc m = medium(true, 20.0f);
  double sigmaT = m.sigma_a[1] + m.sigma_s_prime[1];
  double mu0 = 0.5;
  for (double tau : {0.5, 2.0}) {
    float thickness = float(tau / sigmaT / 20.0);
    setBox(m, thickness);
    SsLightDesc sun = testing::sunLight(3.0f, 120.0f);  // from below, 60 degrees off the axis
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    for (int method : {SS_METHOD_BRUTE, SS_METHOD_REFERENCE}) {
      Image image = render(method, 16);
      for (int c = 0; c < 3; ++c) {
        double t = thickness * 20.0 * (m.sigma_a[c] + m.sigma_s_prime[c]);
        SlabSolution s = solveSlabByAddingDoubling(albedo(m, c), t, mu0);
        double exact = 3.0 * mu0 * s.transmittedRadiance.back();
        EXPECT_NEAR(image.centreMean(c, 0.5) / exact, 1.0, 0.05)
            << "tau " << tau << " channel " << c << " method " << method;
      }
    }
  }
}

// The tau = 0.5 slab lit from below by a sun of 20 degrees, an opaque board 1 unit under it hiding
// x < 0 (docs/SOFT_SHADOWS.md, "Translucent objects"): the light through the slab is shadowed
// softly, its penumbra about 2 tan(10 degrees) = 0.35 units wide, with none of it under the board
// (the entries behind the board are in the irradiance buffer, their share of the light 0). FULL's
// columns against REFERENCE's, which traces the same rule.
TEST_F(Tabulated, ASoftShadowUnderAThinSlabShadowsWhatCrossesIt) {
  SsMaterialDesc m = medium(true, 20.0f);
  float thickness = float(0.5 / (m.sigma_a[1] + m.sigma_s_prime[1]) / 20.0);
  setBox(m, thickness);
  SsMaterialDesc grey = testing::greyMaterial(0.5f);
  ASSERT_EQ(ssSetMaterial(context, 1, &grey), SS_OK);
  testing::Box board(glm::vec3(-3.0f, -3.0f, -thickness - 1.1f), glm::vec3(0.0f, 3.0f, -thickness - 1.0f));
  SsMeshDesc boardMesh = board.desc(1);
  ASSERT_EQ(ssSetMesh(context, 1, &boardMesh), SS_OK) << ssGetLastError();
  SsCameraDesc camera = testing::topDownCamera(1.0f);  // x in [-1, 1] over the image
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  SsLightDesc sun = testing::sunLight(3.0f, 180.0f);  // from below
  constexpr int kSize = 64;
  // The green channel's mean over the middle rows, per column.
  auto columns = [&](int method, float softDegrees) {
    sun.soft_size = float(softDegrees * M_PI / 180.0);
    EXPECT_EQ(ssSetLights(context, &sun, 1), SS_OK);
    Image image = render(method, kSize);
    std::vector<double> out(kSize, 0.0);
    for (int x = 0; x < kSize; ++x)
      for (int y = kSize / 2 - 8; y < kSize / 2 + 8; ++y) out[size_t(x)] += image.rgba[(size_t(y) * kSize + x) * 4 + 1] / 16.0;
    return out;
  };
  auto band = [&](const std::vector<double>& c, double from, double to) {  // mean over x in [from, to]
    double sum = 0.0;
    int n = 0;
    for (int x = 0; x < kSize; ++x) {
      double u = (x + 0.5) / kSize * 2.0 - 1.0;
      if (u >= from && u <= to) sum += c[size_t(x)], ++n;
    }
    return sum / std::max(n, 1);
  };
  auto width = [&](const std::vector<double>& c) {  // 10-90 % of the lit band, in scene units
    double lit = band(c, 0.6, 1.0);
    auto crossing = [&](double level) {
      for (int x = 0; x + 1 < kSize; ++x)
        if (c[size_t(x)] < level * lit && c[size_t(x + 1)] >= level * lit)
          return x + (level * lit - c[size_t(x)]) / (c[size_t(x + 1)] - c[size_t(x)]);
      return double(kSize);
    };
    return (crossing(0.9) - crossing(0.1)) * 2.0 / kSize;
  };
  std::vector<double> full = columns(SS_METHOD_FULL, 20.0f), reference = columns(SS_METHOD_REFERENCE, 20.0f),
                      hard = columns(SS_METHOD_FULL, 0.0f);
  std::printf("through the slab: lit FULL %.4f REFERENCE %.4f; under the board FULL %.5f REFERENCE %.5f; "
              "penumbra 10-90 %% FULL %.3f REFERENCE %.3f, hard FULL %.3f\n",
              band(full, 0.6, 1.0), band(reference, 0.6, 1.0), band(full, -1.0, -0.5), band(reference, -1.0, -0.5),
              width(full), width(reference), width(hard));
  EXPECT_NEAR(band(full, 0.6, 1.0) / band(reference, 0.6, 1.0), 1.0, 0.05);
  EXPECT_LT(band(full, -1.0, -0.5), 0.01 * band(full, 0.6, 1.0));
  EXPECT_LT(band(reference, -1.0, -0.5), 0.01 * band(reference, 0.6, 1.0));
  EXPECT_NEAR(width(full) / width(reference), 1.0, 0.2);
  EXPECT_GT(width(reference), 0.2);
  EXPECT_LT(width(hard), 0.6 * width(full));
}

}  // namespace
}  // namespace subsplat
