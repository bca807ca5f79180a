// The C API rejects bad input with a status and a message, and never crashes.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "material/dipole.h"
#include "material/splat_kernel.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class Api : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { EXPECT_EQ(ssReleaseContext(context), SS_OK); }
  static std::string error() { return ssGetLastError(); }

  testing::EglContext gl;
  SsContext context = nullptr;
  testing::Quad quad;
};

TEST(ApiWithoutContext, NewContextFailsCleanlyWithoutGl) {
  SsContext c = reinterpret_cast<SsContext>(0x1);
  EXPECT_EQ(ssNewContext(&c), SS_GL_ERROR);
  EXPECT_EQ(c, nullptr);
  EXPECT_NE(std::string(ssGetLastError()).find("no OpenGL context"), std::string::npos);
}

// The add-on reads a Principled BSDF's colour by inverting Rd_total: it asks the library's one
// implementation, which is the dipole's own total, and bad input is refused.
TEST(ApiWithoutContext, DipoleTotalReflectanceIsTheDipolesAndRefusesBadInput) {
  const double albedo[] = {0.0, 0.25, 0.5, 0.9, 0.999, 1.0};
  double out[6] = {};
  ASSERT_EQ(ssDipoleTotalReflectance(6, albedo, 1.3, out), SS_OK) << ssGetLastError();
  for (int i = 0; i < 6; ++i)
    EXPECT_DOUBLE_EQ(out[i], Dipole({1.0 - albedo[i], albedo[i], 1.3}).totalReflectance()) << albedo[i];
  EXPECT_EQ(ssDipoleTotalReflectance(0, nullptr, 1.3, nullptr), SS_OK);
  EXPECT_EQ(ssDipoleTotalReflectance(1, nullptr, 1.3, out), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssDipoleTotalReflectance(1, albedo, 1.3, nullptr), SS_INVALID_ARGUMENT);
  const double outside[] = {1.5}, notANumber[] = {std::nan("")};
  EXPECT_EQ(ssDipoleTotalReflectance(1, outside, 1.3, out), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("reduced albedo 0"), std::string::npos) << ssGetLastError();
  EXPECT_EQ(ssDipoleTotalReflectance(1, notANumber, 1.3, out), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssDipoleTotalReflectance(1, albedo, std::nan(""), out), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssDipoleTotalReflectance(1, albedo, 0.0, out), SS_INVALID_ARGUMENT);
}

TEST(ApiWithoutContext, NullPointersAreRejected) {
  EXPECT_EQ(ssNewContext(nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssReleaseContext(nullptr), SS_INVALID_HANDLE);
  EXPECT_EQ(ssRender(nullptr, 4, 4, nullptr), SS_INVALID_HANDLE);
  EXPECT_EQ(ssSetSplatBudget(nullptr, 1000), SS_INVALID_HANDLE);
  EXPECT_EQ(ssGetProfileInfo(nullptr, nullptr), SS_INVALID_ARGUMENT);
  uint64_t notAContext[4] = {0, 0, 0, 0};
  EXPECT_EQ(ssSetLights(reinterpret_cast<SsContext>(notAContext), nullptr, 0), SS_INVALID_HANDLE);
  EXPECT_NE(std::string(ssGetLastError()).find("not a live subsplat context"), std::string::npos);
}

// A released handle is refused, never read: releasing twice, or using a released handle, fails with
// SS_INVALID_HANDLE (the memory it pointed to may belong to something else by then).
TEST(ApiResources, ReleasingAContextOrProfileSetTwiceIsAnError) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssReleaseContext(context), SS_OK) << ssGetLastError();
  EXPECT_EQ(ssReleaseContext(context), SS_INVALID_HANDLE);
  EXPECT_NE(std::string(ssGetLastError()).find("not a live subsplat context"), std::string::npos) << ssGetLastError();
  SsSettings settings = ssDefaultSettings();
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_HANDLE);

  const float a[3] = {0.01f, 0.02f, 0.03f}, s[3] = {1.0f, 1.0f, 1.0f};
  SsProfileSet set = nullptr;
  ASSERT_EQ(ssNewProfileSetFromDipoles(1, 1, a, s, 1.3f, 0.0f, SS_PROFILE_DIPOLE, &set), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssReleaseProfileSet(set), SS_OK) << ssGetLastError();
  EXPECT_EQ(ssReleaseProfileSet(set), SS_INVALID_HANDLE);
  EXPECT_NE(std::string(ssGetLastError()).find("not a live subsplat profile set"), std::string::npos)
      << ssGetLastError();
  SsProfileSetInfo info{};
  EXPECT_EQ(ssGetProfileSetInfo(set, &info), SS_INVALID_HANDLE);
}

// The layouts a binding checks its structs against are the compiler's.
TEST(ApiLayout, StructLayoutsAreTheCompilersAndUnknownNamesAreRefused) {
  uint32_t offset = 7, size = 7;
  ASSERT_EQ(ssGetStructLayout("SsSettings", nullptr, &offset, &size), SS_OK) << ssGetLastError();
  EXPECT_EQ(offset, 0u);
  EXPECT_EQ(size, sizeof(SsSettings));
  ASSERT_EQ(ssGetStructLayout("SsSettings", "target_error", &offset, &size), SS_OK) << ssGetLastError();
  EXPECT_EQ(offset, offsetof(SsSettings, target_error));
  EXPECT_EQ(size, sizeof(float));
  ASSERT_EQ(ssGetStructLayout("SsStats", "stage_ms", &offset, &size), SS_OK) << ssGetLastError();
  EXPECT_EQ(offset, offsetof(SsStats, stage_ms));
  EXPECT_EQ(size, sizeof(double) * SS_STAGE_COUNT);
  ASSERT_EQ(ssGetStructLayout("SsMaterialDesc", "profiles", &offset, &size), SS_OK) << ssGetLastError();
  EXPECT_EQ(offset, offsetof(SsMaterialDesc, profiles));
  EXPECT_EQ(size, sizeof(SsProfileSet));

  EXPECT_EQ(ssGetStructLayout("SsNothing", nullptr, &offset, &size), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("unknown struct 'SsNothing'"), std::string::npos) << ssGetLastError();
  EXPECT_EQ(ssGetStructLayout("SsSettings", "quality", &offset, &size), SS_INVALID_ARGUMENT);
  EXPECT_NE(std::string(ssGetLastError()).find("SsSettings has no field 'quality'"), std::string::npos)
      << ssGetLastError();
  EXPECT_EQ(ssGetStructLayout(nullptr, nullptr, &offset, &size), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssGetStructLayout("SsSettings", nullptr, nullptr, &size), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssGetStructLayout("SsSettings", nullptr, &offset, nullptr), SS_INVALID_ARGUMENT);
}

// ssDefaultSettings are what a new context starts with, and a context takes them as they are.
TEST(ApiSettings, DefaultSettingsAreANewContextsSettings) {
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  SsSettings fresh{};
  ASSERT_EQ(ssGetSettings(context, &fresh), SS_OK);
  const SsSettings defaults = ssDefaultSettings();
  EXPECT_EQ(std::memcmp(&fresh, &defaults, sizeof(SsSettings)), 0);
  EXPECT_EQ(defaults.method, SS_METHOD_BRUTE);
  EXPECT_FLOAT_EQ(defaults.lambda_z, 8.0f);
  EXPECT_EQ(ssSetSettings(context, &defaults), SS_OK) << ssGetLastError();
  EXPECT_EQ(ssReleaseContext(context), SS_OK);
}

SsResourceCounts resourceCounts() {
  SsResourceCounts counts{};
  EXPECT_EQ(ssGetResourceCounts(&counts), SS_OK) << ssGetLastError();
  return counts;
}

TEST(ApiResources, RenderingAndReleasingLeavesNoHandleOrGlObjectBehind) {
  EXPECT_EQ(ssGetResourceCounts(nullptr), SS_INVALID_ARGUMENT);
  testing::EglContext gl;
  const SsResourceCounts before = resourceCounts();
  testing::Sphere sphere;
  for (int round = 0; round < 3; ++round) {
    SsContext context = nullptr;
    ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
    ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
    std::vector<float> rgba(32 * 32 * 4);
    for (SsMethod method : {SS_METHOD_BRUTE, SS_METHOD_FULL}) {
      SsSettings settings{};
      ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
      settings.method = method;
      settings.irradiance_resolution = 64;
      ASSERT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
      ASSERT_EQ(ssRender(context, 32, 32, rgba.data()), SS_OK) << ssGetLastError();
    }
    const SsResourceCounts during = resourceCounts();
    EXPECT_EQ(during.contexts, before.contexts + 1);
    EXPECT_GT(during.textures, before.textures);
    EXPECT_GT(during.buffers, before.buffers);
    EXPECT_GT(during.programs, before.programs);
    ASSERT_EQ(ssReleaseContext(context), SS_OK);
    const SsResourceCounts after = resourceCounts();
    EXPECT_EQ(after.contexts, before.contexts);
    EXPECT_EQ(after.textures, before.textures);
    EXPECT_EQ(after.buffers, before.buffers);
    EXPECT_EQ(after.framebuffers, before.framebuffers);
    EXPECT_EQ(after.vertex_arrays, before.vertex_arrays);
    EXPECT_EQ(after.programs, before.programs);
    EXPECT_EQ(after.queries, before.queries);
    EXPECT_EQ(after.orphaned_gl_objects, before.orphaned_gl_objects);
  }
}

// A dipole's splat kernel is built once per process, not once per context: Blender's UI makes a
// context for each F12 render and for each viewport, and they find the kernels of the materials
// they had. A changed dipole gets a kernel of its own.
TEST(ApiMaterials, ContextsShareTheKernelOfTheSameDipole) {
  testing::EglContext gl;
  SsMaterialDesc skin = testing::skinMaterial(123.0f);  // a scale no other test uses
  auto setIn = [](const SsMaterialDesc& material) {
    SsContext context = nullptr;
    ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssSetMaterial(context, 0, &material), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssReleaseContext(context), SS_OK);
  };
  const uint64_t before = SplatKernel::builtCount();
  for (int round = 0; round < 3; ++round) setIn(skin);
  EXPECT_EQ(SplatKernel::builtCount(), before + 1);
  skin.mm_per_unit = 124.0f;
  setIn(skin);
  EXPECT_EQ(SplatKernel::builtCount(), before + 2);
}

// The memory budget: a mesh or a frame's buffers beyond it fail with SS_LIMIT_EXCEEDED naming
// what needed the memory, before the GL allocates; within it again, the same context renders.
TEST(ApiMemory, MeshesAndBuffersBeyondTheBudgetFailCleanlyAndTheContextRecovers) {
  uint64_t used = 0, budget = 0;
  EXPECT_EQ(ssGetMemoryUsage(&used, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK);  // without a context, 0 until measured
  EXPECT_EQ(ssSetMemoryBudget(1000), SS_INVALID_ARGUMENT);
  testing::EglContext gl;
  ASSERT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK) << ssGetLastError();
  EXPECT_GT(budget, uint64_t(256) << 20) << "the automatic budget of this machine";
  const uint64_t before = used;

  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::Sphere sphere(256, 128);  // 33 k vertices: about 1.8 MiB of GPU buffers
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
  ASSERT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK);
  const uint64_t withScene = used;
  EXPECT_GT(withScene, before + (uint64_t(1) << 20));

  ASSERT_EQ(ssSetMemoryBudget(withScene + (uint64_t(1) << 20)), SS_OK);
  SsMeshDesc big = sphere.desc({0, 0, 0}, 0.3f, 0);
  EXPECT_EQ(ssSetMesh(context, 7, &big), SS_LIMIT_EXCEEDED);
  std::string message = ssGetLastError();
  EXPECT_NE(message.find("mesh 7 ("), std::string::npos) << message;
  EXPECT_NE(message.find("memory budget"), std::string::npos) << message;
  ASSERT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK);
  EXPECT_EQ(used, withScene) << "nothing of the refused mesh stays allocated";

  std::vector<float> rgba(size_t(256) * 256 * 4);
  SsSettings settings{};
  ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
  settings.method = SS_METHOD_FULL;
  settings.irradiance_resolution = 256;
  ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  EXPECT_EQ(ssRender(context, 256, 256, rgba.data()), SS_LIMIT_EXCEEDED);
  message = ssGetLastError();
  EXPECT_NE(message.find("buffers"), std::string::npos) << message;
  std::printf("the budget's message: %s\n", message.c_str());
  EXPECT_NE(message.find("memory budget"), std::string::npos) << message;

  ASSERT_EQ(ssSetMemoryBudget(0), SS_OK);
  ASSERT_EQ(ssRender(context, 256, 256, rgba.data()), SS_OK) << ssGetLastError();
  double sum = 0.0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i];
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_GT(sum, 0.0) << "the sphere renders once the budget allows it";
  ASSERT_EQ(ssReleaseContext(context), SS_OK);
  ASSERT_EQ(ssGetMemoryUsage(&used, &budget), SS_OK);
  EXPECT_EQ(used, before) << "releasing the context frees every byte it held";
}

// With another OpenGL context current, a context refuses GL work; released there, its GL
// objects wait for their own context and are deleted by the next call made in it.
TEST(ApiResources, AnotherGlContextIsRefusedAndReleasingThereWaitsForTheOwner) {
  testing::EglContext other;
  testing::EglContext owner;  // current
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::Sphere sphere;
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
  std::vector<float> rgba(16 * 16 * 4);
  ASSERT_EQ(ssRender(context, 16, 16, rgba.data()), SS_OK) << ssGetLastError();
  const SsResourceCounts before = resourceCounts();
  const int64_t held = before.textures + before.buffers + before.framebuffers + before.vertex_arrays +
                       before.programs + before.queries;
  ASSERT_TRUE(other.makeCurrent());  // the names of `owner`'s objects mean nothing here
  EXPECT_EQ(ssRender(context, 16, 16, rgba.data()), SS_GL_ERROR);
  EXPECT_NE(std::string(ssGetLastError()).find("not the one this context was created in"), std::string::npos)
      << ssGetLastError();
  SsMeshDesc mesh = sphere.desc(glm::vec3(0.0f), 0.3f, 0);
  EXPECT_EQ(ssSetMesh(context, 0, &mesh), SS_GL_ERROR);
  EXPECT_EQ(ssRemoveMesh(context, 0), SS_GL_ERROR);
  ASSERT_EQ(ssReleaseContext(context), SS_OK) << ssGetLastError();
  const SsResourceCounts released = resourceCounts();
  EXPECT_EQ(released.contexts, before.contexts - 1);
  EXPECT_EQ(released.textures + released.buffers + released.framebuffers + released.vertex_arrays +
                released.programs + released.queries,
            0);
  EXPECT_EQ(released.orphaned_gl_objects - before.orphaned_gl_objects, held);
  SsContext next = nullptr;  // a context made in `other` leaves them waiting
  ASSERT_EQ(ssNewContext(&next), SS_OK);
  EXPECT_EQ(resourceCounts().orphaned_gl_objects, released.orphaned_gl_objects);
  ASSERT_EQ(ssReleaseContext(next), SS_OK);
  ASSERT_TRUE(owner.makeCurrent());  // the next call made in `owner` deletes them
  ASSERT_EQ(ssNewContext(&next), SS_OK);
  EXPECT_EQ(resourceCounts().orphaned_gl_objects, before.orphaned_gl_objects);
  ASSERT_EQ(ssReleaseContext(next), SS_OK);
}

std::string glState() {
  std::vector<char> text(1 << 16);
  uint32_t length = 0;
  EXPECT_EQ(ssDescribeGlState(text.data(), uint32_t(text.size()), &length), SS_OK) << ssGetLastError();
  return std::string(text.data(), length);
}

// The library leaves the host's GL state as it found it: every item ssDescribeGlState reports
// (queried apart from StateGuard) is the same after uploads, renders and passes of each method.
TEST(ApiGlState, EveryCallLeavesTheHostStateAsItWas) {
  testing::EglContext gl;
  char tiny[4];
  EXPECT_EQ(ssDescribeGlState(tiny, sizeof tiny, nullptr), SS_LIMIT_EXCEEDED);
  EXPECT_EQ(ssDescribeGlState(nullptr, 0, nullptr), SS_INVALID_ARGUMENT);
  // A host state unlike the defaults: its own framebuffer, vertex array, buffers, textures,
  // blending, culling, scissor, viewport and pixel store.
  GLuint framebuffer = 0, colour = 0, vertexArray = 0, buffer = 0, texture = 0;
  glGenTextures(1, &colour);
  glBindTexture(GL_TEXTURE_2D, colour);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 8, 8);
  glGenFramebuffers(1, &framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glFramebufferTexture(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, colour, 0);
  glGenVertexArrays(1, &vertexArray);
  glBindVertexArray(vertexArray);
  glGenBuffers(1, &buffer);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBindBuffer(GL_UNIFORM_BUFFER, buffer);
  glGenTextures(1, &texture);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, texture);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_CULL_FACE);
  glEnable(GL_SCISSOR_TEST);
  glScissor(1, 2, 3, 4);
  glViewport(0, 0, 7, 5);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ROW_LENGTH, 3);
  glDepthMask(GL_FALSE);
  glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
  const std::string before = glState();
  ASSERT_FALSE(before.empty());

  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::Sphere sphere;
  ASSERT_EQ(testing::setLitSphere(context, sphere, testing::skinMaterial(100.0f)), SS_OK) << ssGetLastError();
  EXPECT_EQ(testing::changedLines(before, glState()), "") << "after the uploads";
  std::vector<float> rgba(24 * 24 * 4);
  for (SsMethod method : {SS_METHOD_BRUTE, SS_METHOD_MULTIRES, SS_METHOD_ADAPTIVE, SS_METHOD_FULL}) {
    SsSettings settings{};
    ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
    settings.method = method;
    settings.irradiance_resolution = 64;
    settings.debug_passes = 1;
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
    ASSERT_EQ(ssRender(context, 24, 24, rgba.data()), SS_OK) << ssGetLastError();
    EXPECT_EQ(testing::changedLines(before, glState()), "") << "after a render, method " << method;
    for (int32_t pass : {SS_PASS_EXITANCE, SS_PASS_SELECTION, SS_PASS_LEVEL_EXITANCE})
      ASSERT_EQ(ssGetPass(context, pass, 24, 24, rgba.data()), SS_OK) << ssGetLastError();
    EXPECT_EQ(testing::changedLines(before, glState()), "") << "after the passes, method " << method;
  }
  ASSERT_EQ(ssRemoveMesh(context, 0), SS_OK);
  ASSERT_EQ(ssReleaseContext(context), SS_OK);
  EXPECT_EQ(testing::changedLines(before, glState()), "") << "after the release";
  glDeleteTextures(1, &texture);
  glDeleteBuffers(1, &buffer);
  glDeleteVertexArrays(1, &vertexArray);
  glDeleteFramebuffers(1, &framebuffer);
  glDeleteTextures(1, &colour);
}

TEST_F(Api, NaNPositionIsRejectedWithTheVertex) {
  std::vector<float> positions = quad.positions;
  positions[7] = std::numeric_limits<float>::quiet_NaN();
  SsMeshDesc mesh = quad.desc(1.0f, 0);
  mesh.positions = positions.data();
  EXPECT_EQ(ssSetMesh(context, 7, &mesh), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("mesh 7: vertex 2 has a non-finite position"), std::string::npos) << error();
}

TEST_F(Api, IndexOutOfRangeIsRejected) {
  std::vector<uint32_t> indices = quad.indices;
  indices[4] = 4;
  SsMeshDesc mesh = quad.desc(1.0f, 0);
  mesh.indices = indices.data();
  EXPECT_EQ(ssSetMesh(context, 1, &mesh), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("out of range"), std::string::npos) << error();
}

TEST_F(Api, EmptyMeshAndNullArraysAreRejected) {
  SsMeshDesc mesh = quad.desc(1.0f, 0);
  mesh.triangle_count = 0;
  EXPECT_EQ(ssSetMesh(context, 1, &mesh), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("empty"), std::string::npos) << error();
  mesh = quad.desc(1.0f, 0);
  mesh.positions = nullptr;
  EXPECT_EQ(ssSetMesh(context, 1, &mesh), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssSetMesh(context, 1, nullptr), SS_INVALID_ARGUMENT);
}

TEST_F(Api, ZeroAndAbsurdRenderSizesAreRejected) {
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  float pixel[4];
  EXPECT_EQ(ssRender(context, 0, 10, pixel), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssRender(context, 10, -1, pixel), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssRender(context, 1, 1, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssRender(context, 1 << 20, 1, pixel), SS_LIMIT_EXCEEDED);
  SsSettings settings = ssDefaultSettings();
  settings.irradiance_resolution = 8;  // 0 is automatic; below 16 is refused
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("irradiance resolution"), std::string::npos) << error();
  settings.irradiance_resolution = -1;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_INVALID_ARGUMENT);
  settings.irradiance_resolution = 0;
  EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << error();
}

TEST_F(Api, BadMaterialsAreRejectedWithTheValue) {
  SsMaterialDesc m = testing::marbleMaterial(20.0f);
  m.sigma_a[1] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(ssSetMaterial(context, 0, &m), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("sigma_a"), std::string::npos) << error();
  m = testing::marbleMaterial(20.0f);
  m.eta = 0.5f;
  EXPECT_EQ(ssSetMaterial(context, 0, &m), SS_INVALID_ARGUMENT);
  m = testing::marbleMaterial(0.0f);
  EXPECT_EQ(ssSetMaterial(context, 0, &m), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("mm_per_unit"), std::string::npos) << error();
}

TEST_F(Api, MeshWithUnsetMaterialFailsAtRender) {
  SsMeshDesc mesh = quad.desc(1.0f, 42);
  ASSERT_EQ(ssSetMesh(context, 3, &mesh), SS_OK) << error();
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  std::vector<float> image(16 * 16 * 4);
  EXPECT_EQ(ssRender(context, 16, 16, image.data()), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("material 42, which was never set"), std::string::npos) << error();
}

TEST_F(Api, RenderWithoutCameraIsAnError) {
  std::vector<float> image(4 * 4 * 4);
  EXPECT_EQ(ssRender(context, 4, 4, image.data()), SS_INVALID_ARGUMENT);
  EXPECT_NE(error().find("no camera"), std::string::npos);
}

TEST_F(Api, BadLightsAreRejected) {
  SsLightDesc light = testing::sunLight(1.0f, 0.0f);
  light.direction[0] = light.direction[1] = light.direction[2] = 0.0f;
  EXPECT_EQ(ssSetLights(context, &light, 1), SS_INVALID_ARGUMENT);
  light = testing::sunLight(std::nanf(""), 0.0f);
  EXPECT_EQ(ssSetLights(context, &light, 1), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssSetLights(context, nullptr, 2), SS_INVALID_ARGUMENT);
}

}  // namespace
}  // namespace subsplat
