// The CPU scene needs no GL: a scene file saved and loaded again, and
// REFERENCE rendered from both, with no GL context on this thread.
#include <gtest/gtest.h>

#include <epoxy/egl.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "reference/reference_renderer.h"
#include "scene.h"
#include "scene_file.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

std::vector<float> renderReference(const Scene& scene, int width, int height) {
  ReferenceOptions options;
  options.samples = 4000;
  std::vector<float> rgba(size_t(width) * height * 4);
  SsStats stats{};
  ReferenceRenderer reference;
  reference.render(scene, options, width, height, rgba.data(), nullptr, stats);
  return rgba;
}

TEST(CpuScene, SceneFilesAndReferenceNeedNoGlContext) {
  ASSERT_EQ(eglGetCurrentContext(), EGL_NO_CONTEXT) << "this test runs without a GL context";
  Scene scene;
  testing::Sphere sphere(24, 12);
  scene.setMaterial(0, testing::marbleMaterial(100.0f));
  scene.setMesh(3, sphere.desc({0, 0, 0}, 0.3f, 0));
  SsLightDesc sun = testing::sunLight(3.0f, 30.0f);
  scene.setLights(&sun, 1);
  scene.setCamera(testing::topDownCamera(0.5f));
  SsSettings settings{};  // zero: the defaults, as a scene file stores what it was given
  settings.method = SS_METHOD_REFERENCE;
  settings.irradiance_resolution = 256;
  settings.reference_samples = 4000;

  std::string path = ::testing::TempDir() + "cpu_scene.ssscene";
  saveScene(scene, settings, {16, 12}, path);
  Scene loaded;
  SsSettings read{};
  FrameSize frame = loadScene(loaded, [&](const SsSettings& s) { read = s; }, path);
  std::remove(path.c_str());
  EXPECT_EQ(frame.width, 16);
  EXPECT_EQ(frame.height, 12);
  EXPECT_EQ(std::memcmp(&read, &settings, sizeof settings), 0);
  ASSERT_EQ(loaded.meshes().size(), 1u);
  const Mesh& a = scene.meshes().at(3);
  const Mesh& b = loaded.meshes().at(3);
  EXPECT_EQ(a.cpuPositions, b.cpuPositions);
  EXPECT_EQ(a.cpuNormals, b.cpuNormals);
  EXPECT_EQ(a.cpuIndices, b.cpuIndices);
  EXPECT_EQ(a.materialIds, b.materialIds);

  scene.resolveMaterials();
  loaded.resolveMaterials();
  std::vector<float> original = renderReference(scene, 16, 12), replayed = renderReference(loaded, 16, 12);
  EXPECT_EQ(original, replayed);
  double sum = 0;
  for (size_t i = 0; i < original.size(); i += 4) sum += original[i];
  EXPECT_GT(sum, 0.0) << "the sphere is lit";
  EXPECT_EQ(eglGetCurrentContext(), EGL_NO_CONTEXT);
}

}  // namespace
}  // namespace subsplat
