// Scene files: a saved scene replays to the same image in a fresh context, and
// damaged files are rejected with a message, never a crash.
#include <cstddef>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class SceneFile : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
    // One file per test: CTest runs the tests in parallel, each in a process of its own.
    path = ::testing::TempDir() + "subsplat_scene_file_test_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".ssscene";
  }
  void TearDown() override {
    EXPECT_EQ(ssReleaseContext(context), SS_OK);
    std::remove(path.c_str());
  }
  std::vector<float> render(SsContext c, int width, int height) {
    std::vector<float> rgba(size_t(width) * height * 4);
    EXPECT_EQ(ssRender(c, width, height, rgba.data()), SS_OK) << ssGetLastError();
    return rgba;
  }
  std::vector<char> fileBytes() const {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  void writeBytes(const std::vector<char>& bytes, size_t count) const {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(count));
  }
  // Rewrites the saved file as an older format `version`: each record's payload goes through
  // edit(tag, payload), which shortens it as that format had it; the sizes follow. Material
  // records lose format 6's texture block (two absent textures and the normal strength) first, and
  // settings format 9's forward_shift and format 8's precomputed_atlas.
  // Returns how many settings records there were.
  int rewriteAs(uint32_t version, const std::function<void(uint32_t, std::vector<char>&)>& edit) const {
    std::vector<char> bytes = fileBytes(), out(bytes.begin(), bytes.begin() + 16);
    std::memcpy(&out[8], &version, 4);
    int settings = 0;
    for (size_t at = 16; at + 16 <= bytes.size();) {
      uint32_t tag;
      uint64_t size;
      std::memcpy(&tag, &bytes[at], 4);
      std::memcpy(&size, &bytes[at + 8], 8);
      std::vector<char> payload(bytes.begin() + std::ptrdiff_t(at + 16), bytes.begin() + std::ptrdiff_t(at + 16 + size));
      if (tag == 1 && version < 6) payload.resize(payload.size() - 12);
      if (tag == 3 && version < 7) {  // lights without world_sh
        uint32_t count;
        std::memcpy(&count, payload.data(), 4);
        for (uint32_t i = count; i-- > 0;)
          erase(payload, 4 + i * sizeof(SsLightDesc) + offsetof(SsLightDesc, world_sh),
                sizeof(SsLightDesc) - offsetof(SsLightDesc, world_sh));
      }
      if (tag == 5 && version < 9 && payload.size() == sizeof(SsSettings))  // settings without forward_shift
        payload.resize(offsetof(SsSettings, forward_shift));
      if (tag == 5 && version < 8 && payload.size() == offsetof(SsSettings, forward_shift))  // nor precomputed_atlas
        payload.resize(offsetof(SsSettings, precomputed_atlas));
      settings += tag == 5;
      edit(tag, payload);
      uint64_t shorter = payload.size();
      out.insert(out.end(), bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + 8));
      const char* sizeBytes = reinterpret_cast<const char*>(&shorter);
      out.insert(out.end(), sizeBytes, sizeBytes + 8);
      out.insert(out.end(), payload.begin(), payload.end());
      at += 16 + size;
    }
    writeBytes(out, out.size());
    return settings;
  }
  // An opaque lit sphere under `settings`, saved and loaded into a fresh context (`loaded`, the
  // caller's to release): `got`, the settings it read.
  void saveAndLoad(const SsSettings& settings, SsContext& loaded, SsSettings& got) {
    SsMaterialDesc opaque{};
    opaque.kind = SS_MATERIAL_OPAQUE;
    ASSERT_EQ(testing::setLitSphere(context, sphere, opaque), SS_OK);
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssNewContext(&loaded), SS_OK);
    ASSERT_EQ(ssLoadScene(loaded, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssGetSettings(loaded, &got), SS_OK);
  }
  // Drops payload[from, from + count).
  static void erase(std::vector<char>& payload, size_t from, size_t count) {
    payload.erase(payload.begin() + std::ptrdiff_t(from), payload.begin() + std::ptrdiff_t(from + count));
  }

  testing::EglContext gl;
  SsContext context = nullptr;
  std::string path;
  testing::Sphere sphere{24, 12};
};

// What a fresh context loads renders the same pixels, with the same settings
// and the frame size of the render before the save.
TEST_F(SceneFile, ReplaysTheSameImageInAFreshContext) {
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK);
  SsSettings settings = ssDefaultSettings();
  settings.method = SS_METHOD_FULL;
  settings.irradiance_resolution = 128;
  settings.levels = 2;
  const float background[4] = {0.1f, 0.2f, 0.3f, 1.0f};
  std::copy(background, background + 4, settings.background);
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  std::vector<float> original = render(context, 48, 40);
  ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();

  SsContext replay = nullptr;
  ASSERT_EQ(ssNewContext(&replay), SS_OK);
  int32_t width = -1, height = -1;
  ASSERT_EQ(ssLoadScene(replay, path.c_str(), &width, &height), SS_OK) << ssGetLastError();
  EXPECT_EQ(width, 48);
  EXPECT_EQ(height, 40);
  std::vector<float> replayed = render(replay, width, height);
  SsStats a{}, b{};
  ASSERT_EQ(ssGetStats(context, &a), SS_OK);
  ASSERT_EQ(ssGetStats(replay, &b), SS_OK);
  EXPECT_EQ(b.levels, a.levels) << "the settings travel with the scene";
  EXPECT_EQ(b.splat_levels, a.splat_levels);
  EXPECT_EQ(b.splat_count, a.splat_count);
  size_t differing = 0;
  for (size_t i = 0; i < original.size(); ++i) differing += original[i] != replayed[i];
  EXPECT_EQ(differing, 0u) << "of " << original.size() << " values";
  EXPECT_EQ(ssReleaseContext(replay), SS_OK);
}

// A heterogeneous material travels with its profiles and map: the same pixels.
TEST_F(SceneFile, ReplaysAHeterogeneousMaterial) {
  const float marbleA[3] = {0.0021f, 0.0041f, 0.0071f}, marbleS[3] = {2.19f, 2.62f, 3.00f};
  const float skinA[3] = {0.032f, 0.17f, 0.48f}, skinS[3] = {0.74f, 0.88f, 1.01f};
  std::vector<float> a, s;
  for (int t = 0; t < 16; ++t) {
    bool marble = (t % 4 + t / 4) % 2 == 0;
    a.insert(a.end(), marble ? marbleA : skinA, (marble ? marbleA : skinA) + 3);
    s.insert(s.end(), marble ? marbleS : skinS, (marble ? marbleS : skinS) + 3);
  }
  SsProfileSet set = nullptr;
  ASSERT_EQ(ssNewProfileSetFromDipoles(4, 4, a.data(), s.data(), 1.3f, 0.0f, SS_PROFILE_DIPOLE, &set), SS_OK) << ssGetLastError();
  SsMaterialDesc m = testing::marbleMaterial(100.0f);
  m.kind = SS_MATERIAL_SUBEDIT;
  m.profiles = set;
  ASSERT_EQ(testing::setLitSphere(context, sphere, m), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssReleaseProfileSet(set), SS_OK);
  SsSettings settings = ssDefaultSettings();
  settings.method = SS_METHOD_BRUTE;
  settings.irradiance_resolution = 128;
  settings.background[3] = 1.0f;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  std::vector<float> original = render(context, 32, 32);
  ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();
  SsContext replay = nullptr;
  ASSERT_EQ(ssNewContext(&replay), SS_OK);
  ASSERT_EQ(ssLoadScene(replay, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  EXPECT_EQ(render(replay, 32, 32), original);
  EXPECT_EQ(ssReleaseContext(replay), SS_OK);
}

TEST_F(SceneFile, MissingFileAndNullArgumentsAreRejected) {
  EXPECT_EQ(ssLoadScene(context, "/nonexistent/dir/scene.ssscene", nullptr, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("cannot read /nonexistent/dir/scene.ssscene"), std::string::npos)
      << ssGetLastError();
  EXPECT_EQ(ssSaveScene(context, "/nonexistent/dir/scene.ssscene"), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssSaveScene(context, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssLoadScene(context, nullptr, nullptr, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssSaveScene(nullptr, path.c_str()), SS_INVALID_HANDLE);
}

// Every truncation of a valid file, and every single-byte corruption of its
// header and record headers, is answered with a status: no crash, no hang, and
// after a failure the scene is empty (a render has nothing to show).
TEST_F(SceneFile, DamagedFilesAreRejectedAndLeaveTheSceneEmpty) {
  SsMaterialDesc opaque{};  // (a dipole's kernel tables would make each load slow)
  opaque.kind = SS_MATERIAL_OPAQUE;
  opaque.base_color[0] = opaque.base_color[1] = opaque.base_color[2] = 0.5f;
  ASSERT_EQ(testing::setLitSphere(context, sphere, opaque), SS_OK);
  ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();
  std::vector<char> good = fileBytes();
  ASSERT_GT(good.size(), 64u);
  int rejected = 0;
  for (size_t n = 0; n < good.size(); n += 1 + n / 8) {
    writeBytes(good, n);
    SsStatus status = ssLoadScene(context, path.c_str(), nullptr, nullptr);
    if (n < good.size()) {
      // Cutting exactly between records leaves a valid, shorter scene.
      if (status != SS_OK) ++rejected;
      EXPECT_TRUE(status == SS_OK || status == SS_INVALID_ARGUMENT) << n << ": " << ssGetLastError();
    }
  }
  EXPECT_GT(rejected, 0);
  for (size_t at = 0; at < 40; ++at) {
    std::vector<char> bad = good;
    bad[at] = char(bad[at] ^ 0x5a);
    writeBytes(bad, bad.size());
    SsStatus status = ssLoadScene(context, path.c_str(), nullptr, nullptr);
    EXPECT_TRUE(status == SS_OK || status == SS_INVALID_ARGUMENT) << at << ": " << ssGetLastError();
  }
  writeBytes(good, 20);  // header and half a record
  EXPECT_EQ(ssLoadScene(context, path.c_str(), nullptr, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("truncated"), std::string::npos) << ssGetLastError();
  std::vector<float> rgba(16 * 16 * 4);
  EXPECT_NE(ssRender(context, 16, 16, rgba.data()), SS_OK) << "no camera: the failed load left nothing";
  std::vector<char> notScene(good.begin(), good.end());
  notScene[0] = 'X';
  writeBytes(notScene, notScene.size());
  EXPECT_EQ(ssLoadScene(context, path.c_str(), nullptr, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("is not a subsplat scene file"), std::string::npos);
}

// Format 1 (before SsSettings.target_error, SsMaterialDesc.profile_model and
// SsLightDesc's world and area fields) still loads: its shorter settings record takes the default target.
TEST_F(SceneFile, FormatOneFilesStillLoad) {
  SsMaterialDesc opaque{};
  opaque.kind = SS_MATERIAL_OPAQUE;
  ASSERT_EQ(testing::setLitSphere(context, sphere, opaque), SS_OK);
  SsSettings settings = ssDefaultSettings();
  settings.method = SS_METHOD_FULL;
  settings.irradiance_resolution = 0;
  settings.background[3] = 1.0f;
  settings.target_error = 0.05f;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssSaveScene(context, path.c_str()), SS_OK) << ssGetLastError();
  int found = rewriteAs(1, [](uint32_t tag, std::vector<char>& payload) {
    if (tag == 1)  // a material: drop profile_model, the last field before the profile set
      erase(payload, 4 + offsetof(SsMaterialDesc, profile_model), 4);
    if (tag == 3) {  // lights (rewriteAs left them up to world_sh): drop the fields from world_directions on
      uint32_t count;
      std::memcpy(&count, payload.data(), 4);
      size_t record = offsetof(SsLightDesc, world_sh);
      ASSERT_EQ(payload.size(), 4 + count * record);
      size_t added = record - offsetof(SsLightDesc, world_directions);
      for (uint32_t i = count; i-- > 0;) erase(payload, 4 + (i + 1) * record - added, added);
    }
    if (tag == 5) {  // settings: drop the fields from target_error on
      ASSERT_EQ(payload.size(), offsetof(SsSettings, precomputed_atlas));  // (rewriteAs: format 7's)
      payload.resize(offsetof(SsSettings, target_error));
    }
  });
  ASSERT_EQ(found, 1);
  SsContext old = nullptr;
  ASSERT_EQ(ssNewContext(&old), SS_OK);
  ASSERT_EQ(ssLoadScene(old, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  SsSettings loaded{};
  ASSERT_EQ(ssGetSettings(old, &loaded), SS_OK);
  EXPECT_EQ(loaded.irradiance_resolution, 0);
  EXPECT_EQ(loaded.method, SS_METHOD_FULL);
  EXPECT_FLOAT_EQ(loaded.target_error, 0.01f) << "format 1 takes the default target";
  EXPECT_EQ(ssReleaseContext(old), SS_OK);
}

// Format 5 keeps the anti-aliasing settings; format 4 (before them) loads as one sample at the
// pixel's centre with Blender's default filter, its other settings as written.
TEST_F(SceneFile, AntiAliasingSettingsRoundTripAndFormatFourTakesOneSample) {
  SsSettings settings = ssDefaultSettings();
  settings.target_error = 0.05f;
  settings.samples = 8;
  settings.filter_width = 2.5f;
  settings.first_sample = 3;
  SsContext loaded = nullptr;
  SsSettings got{};
  ASSERT_NO_FATAL_FAILURE(saveAndLoad(settings, loaded, got));
  EXPECT_EQ(got.samples, 8);
  EXPECT_FLOAT_EQ(got.filter_width, 2.5f);
  EXPECT_EQ(got.first_sample, 3);

  int found = rewriteAs(4, [](uint32_t tag, std::vector<char>& payload) {
    if (tag == 5) payload.resize(offsetof(SsSettings, samples));  // settings: drop the fields from samples on
  });
  ASSERT_EQ(found, 1);
  ASSERT_EQ(ssLoadScene(loaded, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssGetSettings(loaded, &got), SS_OK);
  EXPECT_EQ(got.samples, 1);
  EXPECT_FLOAT_EQ(got.filter_width, 1.5f);
  EXPECT_EQ(got.first_sample, 0);
  EXPECT_FLOAT_EQ(got.target_error, 0.05f);
  EXPECT_EQ(ssReleaseContext(loaded), SS_OK);
}

// PRECOMPUTED's atlas setting (format 8) round trips; a format 7 file, which has none, takes the
// UV map where it fits (the default).
TEST_F(SceneFile, PrecomputedAtlasRoundTripsAndFormatSevenTakesTheUvMap) {
  SsSettings settings = ssDefaultSettings();
  EXPECT_EQ(settings.precomputed_atlas, SS_ATLAS_UV_MAP);
  settings.precomputed_atlas = SS_ATLAS_MADE;
  SsContext loaded = nullptr;
  SsSettings got{};
  ASSERT_NO_FATAL_FAILURE(saveAndLoad(settings, loaded, got));
  EXPECT_EQ(got.precomputed_atlas, SS_ATLAS_MADE);
  ASSERT_EQ(rewriteAs(7, [](uint32_t, std::vector<char>&) {}), 1);
  ASSERT_EQ(ssLoadScene(loaded, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssGetSettings(loaded, &got), SS_OK);
  EXPECT_EQ(got.precomputed_atlas, SS_ATLAS_UV_MAP);
  settings.precomputed_atlas = 2;
  EXPECT_EQ(ssSetSettings(loaded, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("precomputed atlas"), std::string::npos) << ssGetLastError();
  EXPECT_EQ(ssReleaseContext(loaded), SS_OK);
}

// The forward shift setting (format 9) round trips; a format 8 file, which has none, takes it on
// (the default); anything but on and off is refused.
TEST_F(SceneFile, ForwardShiftRoundTripsAndFormatEightTakesItOn) {
  SsSettings settings = ssDefaultSettings();
  EXPECT_EQ(settings.forward_shift, SS_FORWARD_SHIFT_ON);
  settings.forward_shift = SS_FORWARD_SHIFT_OFF;
  SsContext loaded = nullptr;
  SsSettings got{};
  ASSERT_NO_FATAL_FAILURE(saveAndLoad(settings, loaded, got));
  EXPECT_EQ(got.forward_shift, SS_FORWARD_SHIFT_OFF);
  ASSERT_EQ(rewriteAs(8, [](uint32_t, std::vector<char>&) {}), 1);
  ASSERT_EQ(ssLoadScene(loaded, path.c_str(), nullptr, nullptr), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssGetSettings(loaded, &got), SS_OK);
  EXPECT_EQ(got.forward_shift, SS_FORWARD_SHIFT_ON);
  settings.forward_shift = 2;
  EXPECT_EQ(ssSetSettings(loaded, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("forward shift"), std::string::npos) << ssGetLastError();
  EXPECT_EQ(ssReleaseContext(loaded), SS_OK);
}

}  // namespace
}  // namespace subsplat
