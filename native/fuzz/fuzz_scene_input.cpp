// libFuzzer target: the mesh, material, light, camera and settings input of the C API, then a
// small render, on arbitrary values (NaN, infinities, out-of-range indices and ids, absurd
// sizes). Arrays always hold as many values as their counts say: the API cannot check a
// pointer's extent, so that part of the contract is the caller's. Nothing may crash or leak.
//   fuzz_scene_input -max_total_time=60 WORK_CORPUS native/fuzz/corpus/scene
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"

namespace {

subsplat::testing::EglContext* gl = nullptr;
SsProfileSet profiles = nullptr;
SsImage image = nullptr;

void floats(FuzzedDataProvider& in, float* out, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    // Mostly ordinary values, sometimes anything (NaN, infinities, huge).
    out[i] = in.ConsumeBool() ? in.ConsumeFloatingPointInRange<float>(-4.0f, 4.0f) : in.ConsumeFloatingPoint<float>();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  gl = new subsplat::testing::EglContext();
  const float sigmaA[3] = {0.03f, 0.17f, 0.48f}, sigmaS[3] = {0.74f, 0.88f, 1.01f};
  if (ssNewProfileSetFromDipoles(1, 1, sigmaA, sigmaS, 1.3f, 0.0f, SS_PROFILE_DIPOLE, &profiles) != SS_OK) __builtin_trap();
  const float rgb[12] = {0.9f, 0.1f, 0.1f, 0.1f, 0.9f, 0.1f, 0.5f, 0.5f, 1.0f, 1.0f, 1.0f, 1.0f};
  const SsImageDesc desc{2, 2, rgb};
  if (ssNewImage(&desc, &image) != SS_OK) __builtin_trap();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  SsContext context = nullptr;
  if (ssNewContext(&context) != SS_OK) __builtin_trap();
  uint64_t heldBefore = 0, budget = 0;
  if (ssGetMemoryUsage(&heldBefore, &budget) != SS_OK) __builtin_trap();
  // A memory budget of 1 to 4 MiB makes some uploads and renders fail part way (SS_LIMIT_EXCEEDED).
  const bool tight = in.ConsumeBool();
  if (tight && ssSetMemoryBudget(in.ConsumeIntegralInRange<uint64_t>(1 << 20, 4 << 20)) != SS_OK) __builtin_trap();

  for (int m = in.ConsumeIntegralInRange(0, 3); m > 0; --m) {
    SsMaterialDesc material{};
    material.kind = in.ConsumeIntegralInRange<int32_t>(-1, 3);
    floats(in, material.base_color, 3);
    floats(in, material.sigma_a, 3);
    floats(in, material.sigma_s_prime, 3);
    floats(in, &material.eta, 1);
    material.mm_per_unit = in.ConsumeBool() ? in.ConsumeFloatingPointInRange<float>(1.0f, 1000.0f)
                                            : in.ConsumeFloatingPoint<float>();
    floats(in, &material.roughness, 1);
    floats(in, &material.specular, 1);
    material.profiles = in.ConsumeBool() ? profiles : nullptr;
    for (SsTextureDesc* texture : {&material.color_texture, &material.normal_texture}) {
      texture->image = in.ConsumeBool() ? image : nullptr;
      if (in.ConsumeBool()) floats(in, texture->transform, 6);
      texture->extension = in.ConsumeIntegralInRange<int32_t>(-1, 3);
      texture->interpolation = in.ConsumeIntegralInRange<int32_t>(-1, 2);
    }
    if (in.ConsumeBool()) floats(in, &material.normal_strength, 1);
    ssSetMaterial(context, in.ConsumeIntegralInRange<uint32_t>(0, 4), &material);
  }
  if (in.ConsumeBool()) {  // an image of arbitrary size and values, made and released
    const uint32_t width = in.ConsumeIntegralInRange<uint32_t>(0, 5), height = in.ConsumeIntegralInRange<uint32_t>(0, 5);
    std::vector<float> rgb(3 * size_t(width) * height);
    floats(in, rgb.data(), rgb.size());
    const SsImageDesc desc{width, height, in.ConsumeBool() ? rgb.data() : nullptr};
    SsImage made = nullptr;
    if (ssNewImage(&desc, &made) == SS_OK && ssReleaseImage(made) != SS_OK) __builtin_trap();
  }
  for (int k = in.ConsumeIntegralInRange(0, 2); k > 0; --k) {
    const uint32_t vertices = in.ConsumeIntegralInRange<uint32_t>(0, 48);
    const uint32_t triangles = in.ConsumeIntegralInRange<uint32_t>(0, 48);
    std::vector<float> positions(3 * vertices), normals(3 * vertices), uvs(2 * vertices);
    std::vector<uint32_t> indices(3 * triangles), materials(triangles);
    floats(in, positions.data(), positions.size());
    floats(in, normals.data(), normals.size());
    floats(in, uvs.data(), uvs.size());
    for (uint32_t& i : indices) i = in.ConsumeIntegralInRange<uint32_t>(0, vertices + 1);
    for (uint32_t& m : materials) m = in.ConsumeIntegralInRange<uint32_t>(0, 5);
    SsMeshDesc mesh{};
    mesh.positions = in.ConsumeBool() ? positions.data() : nullptr;
    mesh.normals = in.ConsumeBool() ? normals.data() : nullptr;
    mesh.uvs = in.ConsumeBool() ? uvs.data() : nullptr;
    mesh.vertex_count = vertices;
    mesh.indices = in.ConsumeBool() ? indices.data() : nullptr;
    mesh.triangle_materials = in.ConsumeBool() ? materials.data() : nullptr;
    mesh.triangle_count = triangles;
    mesh.default_material = in.ConsumeIntegralInRange<uint32_t>(0, 5);
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (int i = 0; i < 16; ++i) mesh.object_to_world[i] = identity[i];
    if (in.ConsumeBool()) floats(in, mesh.object_to_world, 16);
    ssSetMesh(context, in.ConsumeIntegralInRange<uint32_t>(0, 3), &mesh);
  }
  SsLightDesc lights[3] = {};
  const uint32_t lightCount = in.ConsumeIntegralInRange<uint32_t>(0, 3);
  for (uint32_t i = 0; i < lightCount; ++i) {
    lights[i].type = in.ConsumeIntegralInRange<int32_t>(-1, 5);
    floats(in, lights[i].color, 3);
    floats(in, &lights[i].strength, 1);
    floats(in, lights[i].position, 3);
    floats(in, lights[i].direction, 3);
    floats(in, &lights[i].spot_size, 1);
    floats(in, &lights[i].spot_blend, 1);
    lights[i].world_directions = in.ConsumeIntegralInRange<int32_t>(-2, 70);
    lights[i].area_shape = in.ConsumeIntegralInRange<int32_t>(-1, 4);
    floats(in, lights[i].area_axis, 3);
    floats(in, lights[i].area_size, 2);
    floats(in, &lights[i].soft_size, 1);
    if (in.ConsumeBool()) floats(in, lights[i].world_below, 3);
    if (in.ConsumeBool()) floats(in, lights[i].world_sh, 27);  // a world's harmonics (API 17)
  }
  ssSetLights(context, lightCount ? lights : nullptr, lightCount);
  SsCameraDesc camera{};
  const float view[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1};
  const float ortho[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -0.2f, 0, 0, 0, -1, 1};
  for (int i = 0; i < 16; ++i) camera.world_to_view[i] = view[i], camera.view_to_clip[i] = ortho[i];
  if (in.ConsumeBool()) floats(in, camera.world_to_view, 16);
  if (in.ConsumeBool()) floats(in, camera.view_to_clip, 16);
  camera.orthographic = in.ConsumeIntegralInRange<int32_t>(0, 1);
  ssSetCamera(context, &camera);
  if (in.ConsumeBool()) {  // an environment as the background: the image, or none; any rotation and strength
    SsEnvironmentDesc environment{};
    environment.image = in.ConsumeBool() ? image : nullptr;
    if (in.ConsumeBool()) floats(in, environment.rotation, 9);
    floats(in, &environment.strength, 1);
    ssSetEnvironment(context, &environment);
  }
  SsSettings settings{};
  ssGetSettings(context, &settings);
  // Expensive but valid settings only cost time: kept small so that an input runs in milliseconds.
  settings.method = in.ConsumeIntegralInRange<int32_t>(-1, 4);
  settings.irradiance_resolution = in.ConsumeIntegralInRange<int32_t>(-1, 64);
  settings.reference_samples = in.ConsumeIntegralInRange<uint32_t>(1, 3000);  // not 0, the default 2e5
  settings.levels = in.ConsumeIntegralInRange<int32_t>(-1, 9);
  floats(in, &settings.z0_factor, 1);
  floats(in, &settings.alpha, 1);
  floats(in, &settings.epsilon, 1);
  floats(in, &settings.lambda_z, 1);
  floats(in, &settings.lambda_m, 1);
  settings.debug_passes = in.ConsumeIntegralInRange<int32_t>(0, 1);
  settings.samples = in.ConsumeIntegralInRange<int32_t>(-1, 4);  // a few: each is a frame's passes again
  floats(in, &settings.filter_width, 1);
  settings.first_sample = in.ConsumeIntegralInRange<int32_t>(-1, 1000001);
  settings.shadow_resolution = in.ConsumeIntegralInRange<int32_t>(-1, 64);
  ssSetSettings(context, &settings);
  const int32_t width = in.ConsumeIntegralInRange<int32_t>(-1, 12);
  const int32_t height = in.ConsumeIntegralInRange<int32_t>(-1, 12);
  std::vector<float> rgba(4 * size_t(width > 0 ? width : 0) * size_t(height > 0 ? height : 0) + 4);
  SsStatus rendered = ssRender(context, width, height, rgba.data());
  if (rendered == SS_LIMIT_EXCEEDED && tight) {  // the same context, after a failure part way
    if (ssSetMemoryBudget(0) != SS_OK) __builtin_trap();
    rendered = ssRender(context, width, height, rgba.data());
  }
  if (rendered == SS_OK) {
    SsStats stats;
    ssGetStats(context, &stats);
    ssGetPass(context, in.ConsumeIntegralInRange<int32_t>(-1, 4), width, height, rgba.data());
    // A splatting budget (the viewport's): renders that go on where the last stopped, then a
    // change (the camera sent again, or moved) and more. Read last, so older seeds keep their meaning.
    uint64_t splatBudget = in.ConsumeIntegralInRange<uint64_t>(0, 1 << 20);
    if (splatBudget > 0 && ssSetSplatBudget(context, splatBudget) != SS_OK) __builtin_trap();
    for (int again = in.ConsumeIntegralInRange<int>(0, 4); again > 0; --again) {
      if (in.ConsumeBool()) {
        camera.world_to_view[12] += in.ConsumeFloatingPointInRange<float>(-0.1f, 0.1f);
        ssSetCamera(context, &camera);
      }
      if (ssRender(context, width, height, rgba.data()) == SS_OK) ssGetStats(context, &stats);
    }
  }
  if (ssReleaseContext(context) != SS_OK) __builtin_trap();
  if (ssSetMemoryBudget(0) != SS_OK) __builtin_trap();
  uint64_t heldAfter = 0;
  if (ssGetMemoryUsage(&heldAfter, &budget) != SS_OK || heldAfter != heldBefore) __builtin_trap();
  return 0;
}
