// Textures (docs/TEXTURES.md): the look-up the shaders repeat, the images' validation and
// lifetime, an opaque checker's albedo, a translucent tint that scales the light by T, a normal
// map that tilts the shading, GPU against REFERENCE, and scene files that keep them.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "material/texture.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

std::shared_ptr<const TextureImage> cpuImage(uint32_t width, uint32_t height, const std::vector<float>& rgb) {
  SsImageDesc d{width, height, rgb.data()};
  return std::make_shared<const TextureImage>(d);
}

// Texel centres read their texel; half-way between two, the mean; the modes outside [0, 1].
TEST(TextureSample, BilinearBetweenTexelCentresWithEachExtension) {
  Texture t;
  t.image = cpuImage(2, 1, {0.2f, 0.2f, 0.2f, 0.6f, 0.6f, 0.6f});
  EXPECT_NEAR(t.sample({0.25f, 0.5f}).x, 0.2f, 1e-6f);
  EXPECT_NEAR(t.sample({0.75f, 0.5f}).x, 0.6f, 1e-6f);
  EXPECT_NEAR(t.sample({0.5f, 0.5f}).x, 0.4f, 1e-6f);
  EXPECT_NEAR(t.sample({0.0f, 0.5f}).x, 0.4f, 1e-6f);   // REPEAT: the far texel wraps in
  EXPECT_NEAR(t.sample({1.25f, 0.5f}).x, 0.2f, 1e-6f);
  t.extension = SS_TEXTURE_EXTEND;
  EXPECT_NEAR(t.sample({0.0f, 0.5f}).x, 0.2f, 1e-6f);
  EXPECT_NEAR(t.sample({3.0f, 0.5f}).x, 0.6f, 1e-6f);
  t.extension = SS_TEXTURE_CLIP;
  EXPECT_EQ(t.sample({1.5f, 0.5f}), glm::vec3(0.0f));
  EXPECT_NEAR(t.sample({0.25f, 0.5f}).x, 0.2f, 1e-6f);
  t.extension = SS_TEXTURE_REPEAT;
  t.interpolation = SS_TEXTURE_CLOSEST;
  EXPECT_NEAR(t.sample({0.49f, 0.5f}).x, 0.2f, 1e-6f);
  EXPECT_NEAR(t.sample({0.51f, 0.5f}).x, 0.6f, 1e-6f);
  // The transform u' = 2 u + 0.5: u = 0.375 reads u' = 1.25 (texel 0), u = 0.125 reads 0.75 (texel 1).
  t.transform[0] = 2.0f, t.transform[2] = 0.5f;
  EXPECT_NEAR(t.sample({0.375f, 0.5f}).x, 0.2f, 1e-6f);
  EXPECT_NEAR(t.sample({0.125f, 0.5f}).x, 0.6f, 1e-6f);
}

// A normal map's flat texel (0.5, 0.5, 1) leaves the normal; a tilted one tilts it in the UVs'
// frame; strength mixes.
TEST(TextureSample, NormalMapsTiltInTheUvFrame) {
  glm::vec3 n(0, 0, 1), t(2, 0, 0), b(0, 3, 0);
  EXPECT_LT(glm::distance(perturbedNormal({0.5f, 0.5f, 1.0f}, 1.0f, n, t, b), n), 1e-6f);
  float s = std::sin(0.5f), c = std::cos(0.5f);
  glm::vec3 tilted = perturbedNormal({0.5f * (s + 1), 0.5f, 0.5f * (c + 1)}, 1.0f, n, t, b);
  EXPECT_NEAR(tilted.x, s, 1e-3f);
  EXPECT_NEAR(tilted.z, c, 1e-3f);
  glm::vec3 mirrored = perturbedNormal({0.5f * (s + 1), 0.5f, 0.5f * (c + 1)}, 1.0f, n, -t, b);
  EXPECT_NEAR(mirrored.x, -s, 1e-3f);
  glm::vec3 half = perturbedNormal({0.5f * (s + 1), 0.5f, 0.5f * (c + 1)}, 0.5f, n, t, b);
  glm::vec3 expected = glm::normalize(n + 0.5f * (glm::vec3(s, 0, c) - n));
  EXPECT_LT(glm::distance(half, expected), 1e-3f);
  glm::vec3 corners[3] = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
  glm::vec2 uvs[3] = {{0, 0}, {1, 0}, {0, 1}};
  glm::vec3 tangent, bitangent;
  triangleTangents(corners, uvs, tangent, bitangent);
  EXPECT_LT(glm::distance(tangent, glm::vec3(2, 0, 0)), 1e-6f);
  EXPECT_LT(glm::distance(bitangent, glm::vec3(0, 3, 0)), 1e-6f);
}

// Blender's equirectangular convention (Cycles' direction_to_equirectangular): +x is the map's
// middle, +y a quarter to the left of it, +z its top row.
TEST(EnvironmentMap, UvFollowsBlendersConvention) {
  Environment e;
  EXPECT_NEAR(e.uv({1, 0, 0}).x, 0.5f, 1e-6f);
  EXPECT_NEAR(e.uv({0, 1, 0}).x, 0.25f, 1e-6f);
  EXPECT_NEAR(e.uv({0, -1, 0}).x, 0.75f, 1e-6f);
  EXPECT_NEAR(e.uv({0, 0, 1}).y, 1.0f, 1e-6f);
  EXPECT_NEAR(e.uv({1, 0, 0}).y, 0.5f, 1e-6f);
  e.rotation = glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)));
  EXPECT_NEAR(e.uv({0, -1, 0}).x, 0.5f, 1e-6f);  // -y turned onto +x
}

TEST(TextureApi, ImagesAreValidatedAndReleasedOnce) {
  std::vector<float> rgb{0.5f, 0.5f, 0.5f};
  SsImageDesc d{1, 1, rgb.data()};
  SsImage image = nullptr;
  SsResourceCounts before{};
  ASSERT_EQ(ssGetResourceCounts(&before), SS_OK);
  ASSERT_EQ(ssNewImage(&d, &image), SS_OK) << ssGetLastError();
  SsResourceCounts after{};
  ASSERT_EQ(ssGetResourceCounts(&after), SS_OK);
  EXPECT_EQ(after.images, before.images + 1);
  EXPECT_EQ(ssReleaseImage(image), SS_OK);
  EXPECT_EQ(ssReleaseImage(image), SS_INVALID_HANDLE);
  EXPECT_EQ(ssReleaseImage(nullptr), SS_INVALID_HANDLE);
  EXPECT_EQ(ssNewImage(nullptr, &image), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssNewImage(&d, nullptr), SS_INVALID_ARGUMENT);
  rgb[1] = NAN;
  EXPECT_EQ(ssNewImage(&d, &image), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("texel (0, 0) channel 1"), std::string::npos) << ssGetLastError();
  rgb[1] = -0.1f;
  EXPECT_EQ(ssNewImage(&d, &image), SS_INVALID_ARGUMENT);
  rgb[1] = 0.5f;
  d.width = 0;
  EXPECT_EQ(ssNewImage(&d, &image), SS_INVALID_ARGUMENT);
  d.width = 1, d.rgb = nullptr;
  EXPECT_EQ(ssNewImage(&d, &image), SS_INVALID_ARGUMENT);
}

class Textures : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override {
    for (SsImage image : images) ssReleaseImage(image);
    ssReleaseContext(context);
  }
  SsImage image(uint32_t width, uint32_t height, const std::vector<float>& rgb) {
    SsImageDesc d{width, height, rgb.data()};
    SsImage out = nullptr;
    EXPECT_EQ(ssNewImage(&d, &out), SS_OK) << ssGetLastError();
    images.push_back(out);
    return out;
  }
  // Four colours, one per quadrant of UV space: (0, 0) red, (1, 0) green, (0, 1) blue, (1, 1) grey.
  SsImage checker() {
    return image(2, 2, {0.8f, 0.2f, 0.2f, 0.2f, 0.8f, 0.2f, 0.2f, 0.2f, 0.8f, 0.5f, 0.5f, 0.5f});
  }
  // The quad (UVs 0..1 over it) filling the image, seen from above, lit by a sun from above.
  void setQuad(const SsMaterialDesc& material, float incidence = 0.0f) {
    ASSERT_EQ(ssSetMaterial(context, 0, &material), SS_OK) << ssGetLastError();
    SsMeshDesc mesh = quad.desc(1.0f, 0);
    ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK) << ssGetLastError();
    SsCameraDesc camera = testing::topDownCamera(1.0f);
    ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
    SsLightDesc sun = testing::sunLight(3.0f, incidence);
    ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  }
  std::vector<float> render(int method) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = 128;
    settings.reference_samples = 40000;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(kSize) * kSize * 4);
    EXPECT_EQ(ssRender(context, kSize, kSize, rgba.data()), SS_OK) << ssGetLastError();
    return rgba;
  }
  // The mean colour over the 4 x 4 pixels around the centre of quadrant (qx, qy) of the image.
  static glm::vec3 quadrant(const std::vector<float>& rgba, int qx, int qy) {
    glm::vec3 sum(0.0f);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        size_t i = size_t((qy * kSize / 2 + kSize / 4 - 2 + y) * kSize + qx * kSize / 2 + kSize / 4 - 2 + x);
        sum += glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
      }
    return sum / 16.0f;
  }
  static double meanRelativeDifference(const std::vector<float>& a, const std::vector<float>& b) {
    double diff = 0.0, total = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      if (i % 4 != 3) diff += std::abs(double(a[i]) - double(b[i])), total += std::abs(double(b[i]));
    return diff / std::max(total, 1e-30);
  }

  static constexpr int kSize = 64;
  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
  std::vector<SsImage> images;
};

// An opaque material's albedo is base_color x the texture: each quadrant shows its texel's
// albedo x E / pi, in FULL and in REFERENCE.
TEST_F(Textures, OpaqueCheckerShowsAlbedoTimesIrradiance) {
  SsMaterialDesc material = testing::greyMaterial(1.0f);
  material.color_texture.image = checker();
  material.color_texture.interpolation = SS_TEXTURE_CLOSEST;
  setQuad(material);
  const glm::vec3 albedo[4] = {{0.8f, 0.2f, 0.2f}, {0.2f, 0.8f, 0.2f}, {0.2f, 0.2f, 0.8f}, {0.5f, 0.5f, 0.5f}};
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    std::vector<float> rgba = render(method);
    for (int q = 0; q < 4; ++q) {
      glm::vec3 expected = albedo[q] * 3.0f / float(M_PI), got = quadrant(rgba, q % 2, q / 2);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c] / expected[c], 1.0f, 0.01f) << "method " << method << " quadrant " << q << " channel " << c;
    }
  }
}

// A LINEAR texture through a transform (scale 3, offset, REPEAT), random texels: FULL draws what
// REFERENCE computes, pixel for pixel.
TEST_F(Textures, TransformedLinearTextureAgreesWithReference) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(0.05f, 0.95f);
  std::vector<float> rgb(8 * 8 * 3);
  for (float& v : rgb) v = value(random);
  SsMaterialDesc material = testing::greyMaterial(1.0f);
  material.color_texture.image = image(8, 8, rgb);
  const float transform[6] = {3.0f, 0.0f, 0.1f, 0.0f, 3.0f, -0.2f};
  for (int i = 0; i < 6; ++i) material.color_texture.transform[i] = transform[i];
  setQuad(material);
  std::vector<float> full = render(SS_METHOD_FULL), reference = render(SS_METHOD_REFERENCE);
  double difference = meanRelativeDifference(full, reference);
  std::printf("transformed texture: FULL against REFERENCE, mean relative difference %.5f\n", difference);
  if (difference > 0.005) testing::writeComparison("texture_transformed", full, reference, kSize, kSize);
  EXPECT_LT(difference, 0.005);
}

// A translucent slab tinted by T: where the tint is uniform over many scattering ranges, the
// light is scaled by sqrt(T) x sqrt(T) = T; a white texture changes nothing.
TEST_F(Textures, TranslucentTintScalesTheLightByTheTint) {
  SsMaterialDesc material = testing::skinMaterial(40.0f);
  setQuad(material);
  std::vector<float> plainFull = render(SS_METHOD_FULL), plainReference = render(SS_METHOD_REFERENCE);
  material.color_texture.image = image(1, 1, {1.0f, 1.0f, 1.0f});
  setQuad(material);
  EXPECT_LT(meanRelativeDifference(render(SS_METHOD_FULL), plainFull), 1e-3);
  material.color_texture.image = checker();
  material.color_texture.interpolation = SS_TEXTURE_CLOSEST;
  setQuad(material);
  const glm::vec3 tint[4] = {{0.8f, 0.2f, 0.2f}, {0.2f, 0.8f, 0.2f}, {0.2f, 0.2f, 0.8f}, {0.5f, 0.5f, 0.5f}};
  std::vector<float> tintedFull = render(SS_METHOD_FULL), tintedReference = render(SS_METHOD_REFERENCE);
  for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
    const std::vector<float>& tinted = method == SS_METHOD_FULL ? tintedFull : tintedReference;
    const std::vector<float>& plain = method == SS_METHOD_FULL ? plainFull : plainReference;
    for (int q = 0; q < 4; ++q) {
      glm::vec3 ratio = quadrant(tinted, q % 2, q / 2) / quadrant(plain, q % 2, q / 2);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(ratio[c] / tint[q][c], 1.0f, 0.03f) << "method " << method << " quadrant " << q << " channel " << c;
    }
  }
  double difference = meanRelativeDifference(tintedFull, tintedReference);
  std::printf("tinted slab: FULL against REFERENCE, mean relative difference %.4f\n", difference);
  if (difference > 0.03) testing::writeComparison("texture_tinted_slab", tintedFull, tintedReference, kSize, kSize);
  EXPECT_LT(difference, 0.03);
}

// A normal map tilting the normal by 30 degrees along u (strength 1), and half of it (strength
// 0.5): the sun from above gives cos of the tilt x the flat plane's radiance.
TEST_F(Textures, NormalMapTiltsTheShading) {
  const float tilt = glm::radians(30.0f);
  glm::vec3 mapped(std::sin(tilt), 0.0f, std::cos(tilt));
  SsMaterialDesc material = testing::greyMaterial(0.8f);
  glm::vec3 rgb = 0.5f * (mapped + 1.0f);
  material.normal_texture.image = image(1, 1, {rgb.x, rgb.y, rgb.z});
  const float flat = 0.8f * 3.0f / float(M_PI);
  for (float strength : {1.0f, 0.5f}) {
    material.normal_strength = strength;
    setQuad(material);
    glm::vec3 n = glm::normalize(glm::vec3(0, 0, 1) + strength * (mapped - glm::vec3(0, 0, 1)));
    for (int method : {SS_METHOD_FULL, SS_METHOD_REFERENCE}) {
      std::vector<float> rgba = render(method);
      for (int q = 0; q < 4; ++q)
        EXPECT_NEAR(quadrant(rgba, q % 2, q / 2).g / (flat * n.z), 1.0f, 0.01f)
            << "strength " << strength << " method " << method << " quadrant " << q;
    }
  }
}

// An image released after ssSetMaterial stays the material's; a released handle is refused, as
// are a bad transform and unknown modes, with the material named.
TEST_F(Textures, MaterialsKeepTheirImagesAndRefuseBadOnes) {
  SsMaterialDesc material = testing::greyMaterial(1.0f);
  SsImage red = image(1, 1, {0.8f, 0.1f, 0.1f});
  material.color_texture.image = red;
  setQuad(material);
  ASSERT_EQ(ssReleaseImage(red), SS_OK);
  images.clear();
  glm::vec3 centre = quadrant(render(SS_METHOD_FULL), 0, 0);
  EXPECT_NEAR(centre.r / centre.g, 8.0f, 0.1f);
  EXPECT_EQ(ssSetMaterial(context, 1, &material), SS_INVALID_HANDLE);
  EXPECT_NE(std::string(ssGetLastError()).find("material 1: colour texture image"), std::string::npos) << ssGetLastError();
  material.color_texture.image = image(1, 1, {0.5f, 0.5f, 0.5f});
  material.color_texture.transform[0] = NAN;
  EXPECT_EQ(ssSetMaterial(context, 1, &material), SS_INVALID_ARGUMENT);
  material.color_texture.transform[0] = 1.0f;
  material.color_texture.extension = 3;
  EXPECT_EQ(ssSetMaterial(context, 1, &material), SS_INVALID_ARGUMENT);
  material.color_texture.extension = SS_TEXTURE_CLIP;
  material.normal_strength = -1.0f;
  EXPECT_EQ(ssSetMaterial(context, 1, &material), SS_INVALID_ARGUMENT);
  material.normal_strength = 0.0f;
  EXPECT_EQ(ssSetMaterial(context, 1, &material), SS_OK) << ssGetLastError();
}

// The environment is the background where no object is, along each pixel's ray, in FULL as in
// REFERENCE (and the background colour without one); strength scales it; a bad one is refused.
TEST_F(Textures, EnvironmentIsTheBackground) {
  setQuad(testing::greyMaterial(0.5f));
  SsMeshDesc small = quad.desc(0.3f, 0);
  ASSERT_EQ(ssSetMesh(context, 0, &small), SS_OK);
  SsCameraDesc camera{};  // perspective, looking along +x and a little down, 70 degrees wide
  glm::mat4 view = glm::lookAt(glm::vec3(-2, 0, 0.8f), glm::vec3(0, 0, 0), glm::vec3(0, 0, 1));
  glm::mat4 projection = glm::perspective(glm::radians(70.0f), 1.0f, 0.1f, 100.0f);
  std::memcpy(camera.world_to_view, glm::value_ptr(view), sizeof camera.world_to_view);
  std::memcpy(camera.view_to_clip, glm::value_ptr(projection), sizeof camera.view_to_clip);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  std::vector<float> rgb(32 * 16 * 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[size_t((y * 32 + x) * 3 + c)] = 0.2f + 0.15f * float(c) + 0.3f * float(y) / 15.0f +
                                            0.2f * std::sin(float(x) / 32.0f * 6.2831853f);
  SsEnvironmentDesc environment{};
  environment.image = image(32, 16, rgb);
  environment.strength = 2.0f;
  glm::mat3 turn(glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), glm::vec3(0, 0, 1)));
  std::memcpy(environment.rotation, glm::value_ptr(turn), sizeof environment.rotation);
  ASSERT_EQ(ssSetEnvironment(context, &environment), SS_OK) << ssGetLastError();
  std::vector<float> full = render(SS_METHOD_FULL), reference = render(SS_METHOD_REFERENCE);
  double difference = meanRelativeDifference(full, reference);
  std::printf("environment background: FULL against REFERENCE, mean relative difference %.5f\n", difference);
  if (difference > 0.005) testing::writeComparison("texture_environment", full, reference, kSize, kSize);
  EXPECT_LT(difference, 0.005);
  EXPECT_FLOAT_EQ(full[3], 1.0f);  // a background pixel (bottom left): opaque
  environment.strength = 1.0f;
  ASSERT_EQ(ssSetEnvironment(context, &environment), SS_OK);
  std::vector<float> half = render(SS_METHOD_FULL);
  EXPECT_NEAR(half[size_t(4 * (kSize * (kSize - 1)))] / full[size_t(4 * (kSize * (kSize - 1)))], 0.5f, 1e-3f);
  environment.strength = -1.0f;
  EXPECT_EQ(ssSetEnvironment(context, &environment), SS_INVALID_ARGUMENT);
  environment.strength = 1.0f;
  environment.rotation[4] = NAN;
  EXPECT_EQ(ssSetEnvironment(context, &environment), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssSetEnvironment(context, nullptr), SS_INVALID_ARGUMENT);
  SsEnvironmentDesc none{};
  ASSERT_EQ(ssSetEnvironment(context, &none), SS_OK);
  EXPECT_FLOAT_EQ(render(SS_METHOD_FULL)[3], 0.0f);  // the default background: transparent
}

// A scene file keeps the textures and the environment: the replay draws the same image.
TEST_F(Textures, SceneFilesKeepTheTextures) {
  SsMaterialDesc material = testing::skinMaterial(40.0f);
  material.color_texture.image = checker();
  material.normal_texture.image = image(1, 1, {0.6f, 0.5f, 0.95f});
  material.normal_strength = 0.7f;
  setQuad(material, 20.0f);
  SsEnvironmentDesc environment{};
  environment.image = checker();
  environment.strength = 3.0f;
  ASSERT_EQ(ssSetEnvironment(context, &environment), SS_OK) << ssGetLastError();
  SsMeshDesc small = quad.desc(0.5f, 0);  // the environment shows around it
  ASSERT_EQ(ssSetMesh(context, 0, &small), SS_OK);
  std::vector<float> before = render(SS_METHOD_FULL);
  const std::string path = ::testing::TempDir() + "textures.ssscene";
  ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();
  SsContext replay = nullptr;
  ASSERT_EQ(ssNewContext(&replay), SS_OK);
  ASSERT_EQ(ssLoadScene(replay, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  std::vector<float> after(before.size());
  ASSERT_EQ(ssRender(replay, kSize, kSize, after.data()), SS_OK) << ssGetLastError();
  ssReleaseContext(replay);
  EXPECT_LT(meanRelativeDifference(after, before), 1e-5);
}

}  // namespace
}  // namespace subsplat
