// The GL state Blender can trust: around a render, a host state like Blender's (a sampler
// object and a texture of its own on every texture unit, an image on every image unit, a buffer
// on every storage and uniform binding) changes neither the image nor any of those bindings.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

const float kMarbleA[3] = {0.0021f, 0.0041f, 0.0071f}, kMarbleS[3] = {2.19f, 2.62f, 3.00f};
const float kSkinA[3] = {0.032f, 0.17f, 0.48f}, kSkinS[3] = {0.74f, 0.88f, 1.01f};

GLint integer(GLenum what) {
  GLint value = 0;
  glGetIntegerv(what, &value);
  return value;
}

// Every binding a host may hold, over every unit and binding point the driver has (not only
// those the library uses): "name[index]=value" lines.
std::string bindings() {
  std::ostringstream out;
  GLint active = integer(GL_ACTIVE_TEXTURE);
  out << "active_texture=" << active << "\n";
  for (GLint unit = 0; unit < integer(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS); ++unit) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    out << "texture_2d[" << unit << "]=" << integer(GL_TEXTURE_BINDING_2D) << "\n"
        << "texture_2d_array[" << unit << "]=" << integer(GL_TEXTURE_BINDING_2D_ARRAY) << "\n"
        << "texture_buffer[" << unit << "]=" << integer(GL_TEXTURE_BINDING_BUFFER) << "\n"
        << "sampler[" << unit << "]=" << integer(GL_SAMPLER_BINDING) << "\n";
  }
  glActiveTexture(GLenum(active));
  auto indexed = [&](const char* name, GLenum what, GLuint i) {
    GLint64 value = 0;
    glGetInteger64i_v(what, i, &value);
    out << name << "[" << i << "]=" << value << "\n";
  };
  for (GLint i = 0; i < integer(GL_MAX_IMAGE_UNITS); ++i) {
    indexed("image_name", GL_IMAGE_BINDING_NAME, GLuint(i));
    indexed("image_level", GL_IMAGE_BINDING_LEVEL, GLuint(i));
    indexed("image_layered", GL_IMAGE_BINDING_LAYERED, GLuint(i));
    indexed("image_layer", GL_IMAGE_BINDING_LAYER, GLuint(i));
    indexed("image_access", GL_IMAGE_BINDING_ACCESS, GLuint(i));
    indexed("image_format", GL_IMAGE_BINDING_FORMAT, GLuint(i));
  }
  for (GLint i = 0; i < integer(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS); ++i) {
    indexed("shader_storage_buffer", GL_SHADER_STORAGE_BUFFER_BINDING, GLuint(i));
    indexed("shader_storage_start", GL_SHADER_STORAGE_BUFFER_START, GLuint(i));
    indexed("shader_storage_size", GL_SHADER_STORAGE_BUFFER_SIZE, GLuint(i));
  }
  for (GLint i = 0; i < integer(GL_MAX_UNIFORM_BUFFER_BINDINGS); ++i) {
    indexed("uniform_buffer", GL_UNIFORM_BUFFER_BINDING, GLuint(i));
    indexed("uniform_buffer_start", GL_UNIFORM_BUFFER_START, GLuint(i));
    indexed("uniform_buffer_size", GL_UNIFORM_BUFFER_SIZE, GLuint(i));
  }
  for (const auto& [name, what] : std::initializer_list<std::pair<const char*, GLenum>>{
           {"shader_storage_buffer", GL_SHADER_STORAGE_BUFFER_BINDING},
           {"uniform_buffer", GL_UNIFORM_BUFFER_BINDING},
           {"texture_buffer", GL_TEXTURE_BUFFER_BINDING},
           {"array_buffer", GL_ARRAY_BUFFER_BINDING},
           {"pixel_pack_buffer", GL_PIXEL_PACK_BUFFER_BINDING},
           {"pixel_unpack_buffer", GL_PIXEL_UNPACK_BUFFER_BINDING},
           {"draw_indirect_buffer", GL_DRAW_INDIRECT_BUFFER_BINDING},
           {"program", GL_CURRENT_PROGRAM},
           {"vertex_array", GL_VERTEX_ARRAY_BINDING},
           {"draw_framebuffer", GL_DRAW_FRAMEBUFFER_BINDING},
           {"read_framebuffer", GL_READ_FRAMEBUFFER_BINDING}})
    out << name << "=" << integer(what) << "\n";
  return out.str();
}

// What Blender's GPU module leaves bound when it calls a render engine: its own textures of
// every target on every unit, with a sampler object on each (glBindSamplers) whose filtering
// and wrapping differ from the library's (NEAREST, REPEAT), an image on every image unit, and
// buffers on every storage and uniform binding.
class BlenderLikeHostState {
 public:
  BlenderLikeHostState() {
    const GLint units = integer(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS);
    const float texels[4 * 4 * 4] = {0.9f, 0.1f, 0.4f, 1.0f};
    glGenTextures(1, &texture2D_);
    glBindTexture(GL_TEXTURE_2D, texture2D_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, 4, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 4, 4, GL_RGBA, GL_FLOAT, texels);
    glGenTextures(1, &texture2DArray_);
    glBindTexture(GL_TEXTURE_2D_ARRAY, texture2DArray_);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA32F, 4, 4, 2);
    glGenBuffers(1, &buffer_);
    glBindBuffer(GL_TEXTURE_BUFFER, buffer_);
    glBufferData(GL_TEXTURE_BUFFER, 4096, nullptr, GL_STATIC_DRAW);
    glGenTextures(1, &textureBuffer_);
    glBindTexture(GL_TEXTURE_BUFFER, textureBuffer_);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_R32UI, buffer_);
    glGenSamplers(1, &sampler_);
    glSamplerParameteri(sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
      glSamplerParameteri(sampler_, wrap, GL_REPEAT);
    for (GLint unit = 0; unit < units; ++unit) {
      glActiveTexture(GLenum(GL_TEXTURE0 + unit));
      glBindTexture(GL_TEXTURE_2D, texture2D_);
      glBindTexture(GL_TEXTURE_2D_ARRAY, texture2DArray_);
      glBindTexture(GL_TEXTURE_BUFFER, textureBuffer_);
    }
    std::vector<GLuint> samplers(size_t(units), sampler_);
    glBindSamplers(0, units, samplers.data());
    glActiveTexture(GL_TEXTURE5);
    glGenTextures(1, &image_);
    glBindTexture(GL_TEXTURE_2D, image_);
    glTexStorage2D(GL_TEXTURE_2D, 2, GL_RGBA8, 4, 4);
    glBindTexture(GL_TEXTURE_2D, texture2D_);
    for (GLint i = 0; i < integer(GL_MAX_IMAGE_UNITS); ++i)
      glBindImageTexture(GLuint(i), image_, 1, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA8);
    for (GLint i = 0; i < integer(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS); ++i)
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, GLuint(i), buffer_, 256, 512);
    for (GLint i = 0; i < integer(GL_MAX_UNIFORM_BUFFER_BINDINGS); ++i)
      glBindBufferRange(GL_UNIFORM_BUFFER, GLuint(i), buffer_, 256, 256);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer_);
    glBindBuffer(GL_UNIFORM_BUFFER, buffer_);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  }
  ~BlenderLikeHostState() {
    glDeleteSamplers(1, &sampler_);
    for (GLuint t : {texture2D_, texture2DArray_, textureBuffer_, image_}) glDeleteTextures(1, &t);
    glDeleteBuffers(1, &buffer_);
  }

 private:
  GLuint texture2D_ = 0, texture2DArray_ = 0, textureBuffer_ = 0, image_ = 0, buffer_ = 0, sampler_ = 0;
};

class GlState : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override {
    ssReleaseContext(context);
    for (SsProfileSet s : sets) ssReleaseProfileSet(s);
  }
  // A chessboard of marble and skin dipoles as one heterogeneous (SUBEDIT) material on the lit
  // sphere, rendered with FULL over several irradiance levels.
  void setHeterogeneousScene() {
    std::vector<float> a, s;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x) {
        bool marble = (x + y) % 2 == 0;
        a.insert(a.end(), marble ? kMarbleA : kSkinA, (marble ? kMarbleA : kSkinA) + 3);
        s.insert(s.end(), marble ? kMarbleS : kSkinS, (marble ? kMarbleS : kSkinS) + 3);
      }
    SsProfileSet set = nullptr;
    ASSERT_EQ(ssNewProfileSetFromDipoles(8, 4, a.data(), s.data(), 1.3f, 0.0f, SS_PROFILE_DIPOLE, &set), SS_OK) << ssGetLastError();
    sets.push_back(set);
    SsMaterialDesc m = testing::marbleMaterial(100.0f);
    m.kind = SS_MATERIAL_SUBEDIT;
    m.profiles = set;
    ASSERT_EQ(testing::setLitSphere(context, sphere, m), SS_OK) << ssGetLastError();
    SsSettings settings{};
    ASSERT_EQ(ssGetSettings(context, &settings), SS_OK);
    settings.method = SS_METHOD_FULL;
    settings.irradiance_resolution = 128;
    settings.levels = 4;
    settings.samples = 3;  // anti-aliasing's passes and blending too
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK);
  }
  // The rendered image and its exitance pass, one after the other.
  std::vector<float> render() {
    const int size = 48;
    std::vector<float> rgba(size_t(size) * size * 4), exitance(rgba.size());
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, size, size, exitance.data()), SS_OK) << ssGetLastError();
    rgba.insert(rgba.end(), exitance.begin(), exitance.end());
    return rgba;
  }

  testing::EglContext gl;
  SsContext context = nullptr;
  std::vector<SsProfileSet> sets;
  testing::Sphere sphere{32, 16};
};

TEST_F(GlState, BlenderLikeHostStateChangesNeitherTheHeterogeneousImageNorAnyBinding) {
  setHeterogeneousScene();
  const std::vector<float> clean = render();
  SsStats stats{};
  ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
  ASSERT_GT(stats.levels, 1) << "the irradiance hierarchy (and its reduction) must run";
  ASSERT_GT(stats.lit_translucent_pixels, 0u);

  BlenderLikeHostState host;
  const std::string before = bindings();
  const std::vector<float> hosted = render();
  EXPECT_EQ(testing::changedLines(before, bindings()), "") << "bindings the render left changed";
  ASSERT_EQ(hosted.size(), clean.size());
  size_t differing = 0;
  for (size_t i = 0; i < clean.size(); ++i)
    if (std::memcmp(&clean[i], &hosted[i], sizeof(float)) != 0) ++differing;
  EXPECT_EQ(differing, 0u) << "values of the image and exitance pass that differ from the clean-state render";
}

}  // namespace
}  // namespace subsplat
