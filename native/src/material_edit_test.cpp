// MATERIAL_EDIT (issue 23; docs/MATERIAL_EDIT.md): material edits recombined from the precomputed
// transport against FULL's renders of the edited material, and what invalidates the transport.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class MaterialEdit : public ::testing::Test {
 protected:
  static constexpr int kSize = 48;
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  // levels, shadows: SsSettings.levels and shadow_resolution (0: chosen from the scene).
  std::vector<float> render(int method, SsStats* stats = nullptr, int size = kSize, int resolution = 64,
                            int levels = 0, int shadows = 0) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = resolution;
    settings.levels = levels;
    settings.shadow_resolution = shadows;
    // MATERIAL_EDIT's transport is centred on the entry point: FULL and REFERENCE are compared with
    // it under the same model, without the TABULATED model's forward shift (docs/MATERIAL_EDIT.md).
    settings.forward_shift = SS_FORWARD_SHIFT_OFF;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(size) * size * 4);
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    SsStats s{};
    EXPECT_EQ(ssGetStats(context, &s), SS_OK);
    if (stats) *stats = s;
    return rgba;
  }
  testing::EglContext gl;
  SsContext context = nullptr;
};

// Skin1's red R_P is a third of the sphere's radius.
constexpr float kMmPerUnit = 30.0f;

SsMaterialDesc preset(const char* name, int model) {
  SsMaterialDesc m = testing::skinMaterial(kMmPerUnit);
  for (const testing::PresetMedium& p : testing::kPresetMedia)
    if (std::strcmp(p.name, name) == 0) {
      std::memcpy(m.sigma_a, p.sigmaA, sizeof m.sigma_a);
      std::memcpy(m.sigma_s_prime, p.sigmaSPrime, sizeof m.sigma_s_prime);
    }
  m.profile_model = model;
  return m;
}

uint64_t fragments(const SsStats& s) {
  uint64_t sum = 0;
  for (uint64_t f : s.fragment_invocations) sum += f;
  return sum;
}

// The test: three successive edits (sigma_a x 2, sigma_s' x 0.5, a preset change), each
// recombined from the transport precomputed for the first material, within 1 % of FULL's render
// of the edited material (relative RMSE), under each profile model.
TEST_F(MaterialEdit, ThreeSuccessiveEditsMatchFull) {
  testing::Sphere sphere;
  for (int model : {SS_PROFILE_DIPOLE, SS_PROFILE_TABULATED}) {
    SsMaterialDesc material = preset("Skin1", model);
    ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
    SsStats stats{};
    std::vector<float> edit = render(SS_METHOD_MATERIAL_EDIT, &stats);
    EXPECT_EQ(stats.transport_reused, 0);
    EXPECT_GT(stats.precompute_ms, 0.0);
    SsStats precomputation = stats;
    std::vector<float> full = render(SS_METHOD_FULL);
    double error = testing::relativeRmse(edit, full);
    std::printf("model %d, as precomputed: %.4f (precomputation %.0f ms, %llu fragments)\n", model, error,
                stats.precompute_ms, (unsigned long long)fragments(precomputation));
    EXPECT_LT(error, 0.01);
    SsMaterialDesc edits[3] = {material, material, preset("Skin2", model)};
    for (float& a : edits[0].sigma_a) a *= 2.0f;
    for (float& s : edits[1].sigma_s_prime) s *= 0.5f;
    const char* names[3] = {"sigma_a x2", "sigma_s' x0.5", "Skin2"};
    for (int e = 0; e < 3; ++e) {
      ASSERT_EQ(ssSetMaterial(context, 0, &edits[e]), SS_OK) << ssGetLastError();
      edit = render(SS_METHOD_MATERIAL_EDIT, &stats);
      EXPECT_EQ(stats.transport_reused, 1) << names[e];
      EXPECT_EQ(stats.precompute_ms, 0.0) << names[e];
      double editMs = stats.frame_ms;
      uint64_t editFragments = fragments(stats);
      full = render(SS_METHOD_FULL, &stats);
      error = testing::relativeRmse(edit, full);
      std::printf("model %d, %s: %.4f (edit %.0f ms, %llu fragments; FULL %.0f ms, %llu fragments)\n", model,
                  names[e], error, editMs, (unsigned long long)editFragments, stats.frame_ms,
                  (unsigned long long)fragments(stats));
      if (error >= 0.01)
        testing::writeComparison("material_edit_" + std::to_string(model) + "_" + std::to_string(e), edit, full, kSize,
                                 kSize);
      EXPECT_LT(error, 0.01) << names[e];
    }
  }
}

// An edit that changes nothing the direct light reads but the absorption keeps the direct light of
// the render before it and draws no light view, under each model (TABULATED's light through thin
// parts is evaluated again for the edited material: Tabulated.AnEditsLightThroughAThinSlab...); its
// image is the one an edit that draws the direct light again gives; it keeps the camera's G-buffer
// too. A change of the specular level or a render of another method in between draws it again.
TEST_F(MaterialEdit, AnAbsorptionEditKeepsTheDirectLight) {
  testing::Sphere sphere;
  for (int model : {SS_PROFILE_DIPOLE, SS_PROFILE_TABULATED}) {
    SsMaterialDesc material = preset("Skin1", model);
    ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
    SsStats stats{};
    render(SS_METHOD_MATERIAL_EDIT, &stats);
    int views = stats.light_views;
    ASSERT_GT(views, 0);
    SsMaterialDesc absorbing = material, shiny = material;
    for (float& a : absorbing.sigma_a) a *= 2.0f;
    shiny.specular = 0.9f;
    ASSERT_EQ(ssSetMaterial(context, 0, &absorbing), SS_OK);
    std::vector<float> kept = render(SS_METHOD_MATERIAL_EDIT, &stats);
    EXPECT_EQ(stats.transport_reused, 1);
    EXPECT_EQ(stats.light_views, 0) << "the absorption edit drew the direct light again";
    EXPECT_EQ(stats.fragment_invocations[SS_STAGE_BUFFERS], 0u)
        << "the absorption edit drew the camera's G-buffer again (geometry, camera and size as they were)";
    ASSERT_EQ(ssSetMaterial(context, 0, &shiny), SS_OK);
    render(SS_METHOD_MATERIAL_EDIT, &stats);
    EXPECT_EQ(stats.transport_reused, 1);
    EXPECT_EQ(stats.light_views, views) << "the specular edit kept the direct light";
    ASSERT_EQ(ssSetMaterial(context, 0, &absorbing), SS_OK);
    std::vector<float> drawn = render(SS_METHOD_MATERIAL_EDIT, &stats);
    EXPECT_EQ(stats.light_views, views);
    double difference = testing::relativeRmse(kept, drawn);
    std::printf("model %d: kept against drawn direct light: relative RMSE %.2g\n", model, difference);
    if (difference > 1e-6)
      testing::writeComparison("material_edit_kept_direct_" + std::to_string(model), kept, drawn, kSize, kSize);
    EXPECT_LE(difference, 1e-6);
    // Another method's render leaves its own direct light; the next edit draws it again.
    render(SS_METHOD_FULL);
    ASSERT_EQ(ssSetMaterial(context, 0, &material), SS_OK);
    render(SS_METHOD_MATERIAL_EDIT, &stats);
    EXPECT_EQ(stats.transport_reused, 1);
    EXPECT_EQ(stats.light_views, views) << "an edit after FULL kept FULL's direct light";
    EXPECT_GT(stats.fragment_invocations[SS_STAGE_BUFFERS], 0u) << "an edit after FULL kept the G-buffer";
  }
}

// Keeping TABULATED's light through thin parts is a saving, not a need: where the memory budget
// has room for the precomputation but not for that light, the precomputation still succeeds and
// the edit draws the light views again (and still matches).
TEST_F(MaterialEdit, NoRoomForTheKeptLightThroughDrawsTheViewsAgain) {
  constexpr int kWide = 160;
  testing::Sphere sphere;
  SsMaterialDesc material = preset("Skin1", SS_PROFILE_TABULATED), absorbing = material;
  for (float& a : absorbing.sigma_a) a *= 2.0f;
  ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
  SsStats stats{};
  render(SS_METHOD_MATERIAL_EDIT, &stats, kWide, 64, 0, 64);
  uint64_t used = 0, budget = 0;
  ASSERT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK);
  int views = stats.light_views;
  ASSERT_GT(views, 0);
  ASSERT_EQ(ssSetMaterial(context, 0, &absorbing), SS_OK);
  std::vector<float> roomy = render(SS_METHOD_MATERIAL_EDIT, &stats, kWide, 64, 0, 64);
  EXPECT_EQ(stats.light_views, 0);
  // The same in a new context, with half of that light's memory (Shading::keepThrough: two RGBA32F
  // layers a view, and one more image) missing from what the first precomputation held. (What it
  // makes after that light, the shadow maps' copies, is smaller at 64² shadow maps.)
  uint64_t through = uint64_t(kWide) * kWide * (32u * uint64_t(views) + 16u);
  ssReleaseContext(context);
  context = nullptr;
  ASSERT_EQ(ssSetMemoryBudget(used - through / 2), SS_OK);
  struct Restore {
    ~Restore() { ssSetMemoryBudget(0); }
  } restore;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
  render(SS_METHOD_MATERIAL_EDIT, &stats, kWide, 64, 0, 64);
  EXPECT_EQ(stats.transport_reused, 0);
  ASSERT_EQ(ssSetMaterial(context, 0, &absorbing), SS_OK);
  std::vector<float> tight = render(SS_METHOD_MATERIAL_EDIT, &stats, kWide, 64, 0, 64);
  EXPECT_EQ(stats.transport_reused, 1);
  EXPECT_EQ(stats.light_views, views) << "the edit kept a light through it had no room for";
  double difference = testing::relativeRmse(roomy, tight);
  std::printf("kept against drawn light through: relative RMSE %.2g\n", difference);
  EXPECT_LT(difference, 1e-5);
}

// The precomputation's splatting work against FULL's on the sphere (one splatting level): the far
// group of splines is splatted over kSupportGrowth times the material's support, the near group
// only over a tenth of R_P (TransportSplatting). Measured: 1.14 x FULL's fragments (dipole) and
// 1.18 x (TABULATED); 2.02 x and 2.06 x when the near group's quads still reached the whole support.
// The bound, 1.5 x, keeps the near group near.
TEST_F(MaterialEdit, PrecomputationSplatsLittleMoreThanFull) {
  testing::Sphere sphere;
  for (int model : {SS_PROFILE_DIPOLE, SS_PROFILE_TABULATED}) {
    ASSERT_EQ(testing::setLitSphere(context, sphere, preset("Skin1", model)), SS_OK) << ssGetLastError();
    SsStats precomputation{}, full{};
    render(SS_METHOD_MATERIAL_EDIT, &precomputation, kSize, 64, 1);
    render(SS_METHOD_FULL, &full, kSize, 64, 1);
    ASSERT_EQ(precomputation.transport_reused, 0);
    double ratio = double(precomputation.fragment_invocations[SS_STAGE_SPLATTING]) /
                   double(full.fragment_invocations[SS_STAGE_SPLATTING]);
    std::printf("model %d: the precomputation splats %.2f x FULL's fragments\n", model, ratio);
    EXPECT_LT(ratio, 1.5);
  }
}

// The invalidation test: moving a light, a vertex or the camera, or changing the size,
// precomputes the transport again; a material edit alone does not, nor does an unchanged scene.
// An edit the transport cannot carry (another index of refraction, a profile reaching past the
// basis) precomputes again too; a heterogeneous material is rendered as FULL.
TEST_F(MaterialEdit, AnyChangeButTheMaterialPrecomputesAgain) {
  testing::Sphere sphere(24, 12);
  SsMaterialDesc material = preset("Skin1", SS_PROFILE_TABULATED);
  ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
  auto reused = [&](const char* what, int renderSize = 32) {
    SsStats stats{};
    render(SS_METHOD_MATERIAL_EDIT, &stats, renderSize, 32);
    std::printf("%s: %.0f ms\n", what, stats.frame_ms);
    EXPECT_EQ(stats.transport_reused != 0, stats.precompute_ms == 0.0) << what;
    EXPECT_EQ(stats.transport_full_pipeline, 0) << what;
    return stats.transport_reused != 0;
  };
  EXPECT_FALSE(reused("the first render"));
  EXPECT_TRUE(reused("nothing changed"));
  // Its exitance is a pass, as FULL's; it has no debug passes.
  std::vector<float> pass(32 * 32 * 4);
  EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, 32, 32, pass.data()), SS_OK) << ssGetLastError();
  double lit = 0.0;
  for (size_t i = 0; i < pass.size(); i += 4) lit += pass[i] + pass[i + 1] + pass[i + 2];
  EXPECT_GT(lit, 0.0);
  EXPECT_EQ(ssGetPass(context, SS_PASS_SELECTION, 32, 32, pass.data()), SS_INVALID_ARGUMENT);
  SsMaterialDesc edited = material;
  for (float& a : edited.sigma_a) a *= 1.5f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_TRUE(reused("a material edit"));
  // The TABULATED model's incidence factor and side weight are in the transport: recombined after
  // a switch of the model, Skin1 on the lit sphere was 17 % (DIPOLE to TABULATED) and 1.1 % (back)
  // off FULL's image (a scratch measurement, docs/MATERIAL_EDIT.md).
  edited.profile_model = SS_PROFILE_DIPOLE;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("another profile model"));

  SsLightDesc sun = testing::sunLight(3.0f, 60.0f);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  EXPECT_FALSE(reused("a light moved"));
  EXPECT_TRUE(reused("nothing changed after the light"));

  SsMeshDesc mesh = sphere.desc(glm::vec3(0.0f), 0.3f, 0);
  std::vector<float> positions(sphere.positions);
  positions[3 * 100 + 2] += 0.01f;  // one vertex
  mesh.positions = positions.data();
  ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK) << ssGetLastError();
  EXPECT_FALSE(reused("a vertex moved"));

  SsCameraDesc camera = testing::topDownCamera(0.36f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  EXPECT_FALSE(reused("the camera moved"));
  EXPECT_TRUE(reused("nothing changed after the camera"));
  EXPECT_FALSE(reused("another size", 40));
  EXPECT_FALSE(reused("the first size again"));
  EXPECT_TRUE(reused("nothing changed after the size"));

  // The light entering carries the colour texture's tint (sqrt T as it enters) and meets the
  // normal map's normal: either changed precomputes again.
  const std::vector<float> grey(2 * 2 * 3, 0.5f);
  SsImageDesc imageDesc{2, 2, grey.data()};
  SsImage image = nullptr;
  ASSERT_EQ(ssNewImage(&imageDesc, &image), SS_OK) << ssGetLastError();
  edited.color_texture.image = image;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK) << ssGetLastError();
  EXPECT_FALSE(reused("a colour texture"));
  EXPECT_TRUE(reused("nothing changed after the texture"));
  edited.color_texture.transform[0] = 2.0f;
  edited.color_texture.transform[4] = 2.0f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("the colour texture's mapping"));
  edited.color_texture = SsTextureDesc{};
  edited.normal_texture.image = image;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("a normal map instead"));
  edited.normal_strength = 0.5f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("the normal map's strength"));
  EXPECT_EQ(ssReleaseImage(image), SS_OK);
  edited.normal_texture = SsTextureDesc{};
  edited.normal_strength = 0.0f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("no texture"));

  edited.eta = 1.4f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("another index of refraction"));
  for (float& s : edited.sigma_s_prime) s *= 0.05f;
  ASSERT_EQ(ssSetMaterial(context, 0, &edited), SS_OK);
  EXPECT_FALSE(reused("a profile past the basis's reach"));
}

}  // namespace
}  // namespace subsplat
