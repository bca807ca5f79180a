// The light and Fresnel models are written twice: in GLSL for the real-time methods
// (common.glsl) and in C++ for REFERENCE and the dipole (reference/lighting.cpp,
// material/dipole.cpp). A tiny compute shader runs common.glsl's functions on the same inputs
// as the C++ ones, and the two must agree to float precision.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gl/gl.h"
#include "material/dipole.h"
#include "pipeline/pass_helpers.h"
#include "reference/lighting.h"
#include "testing/egl_context.h"

namespace subsplat {
namespace {

// inputs[i]: (eta, cos theta) for Fresnel; a surface point for the lights. outputs[2 i]: the
// Fresnel transmittance, or the direction towards the light; outputs[2 i + 1]: the irradiance
// on a surface facing the light. The storage bindings are the test's own, past the table's.
const char* kEvaluate = R"glsl(
layout(local_size_x = 64) in;
layout(std430, binding = 6) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 7) writeonly buffer Outputs { vec4 outputs[]; };
uniform int count;
uniform int evaluateFresnel;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= count) return;
  vec4 x = inputs[i];
  if (evaluateFresnel != 0) {
    outputs[2 * i] = vec4(fresnelTransmittance(x.x, x.y));
    outputs[2 * i + 1] = vec4(0.0);
  } else {
    outputs[2 * i] = vec4(towardsLight(x.xyz), 0.0);
    outputs[2 * i + 1] = vec4(irradianceFacingLight(x.xyz), 0.0);
  }
}
)glsl";

class ShaderAgreement : public ::testing::Test {
 protected:
  void SetUp() override {
    program = gl::makeComputeProgramFromSource("shader_agreement.comp", kEvaluate);
    glGenBuffers(2, buffers);
  }
  void TearDown() override { glDeleteBuffers(2, buffers); }

  // Runs the shader over `inputs` with the uniforms set now; two outputs per input.
  std::vector<glm::vec4> evaluate(const std::vector<glm::vec4>& inputs, bool fresnel) {
    glUseProgram(program.id());
    glUniform1i(uniform(program.id(), "count"), int(inputs.size()));
    glUniform1i(uniform(program.id(), "evaluateFresnel"), fresnel ? 1 : 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, buffers[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(inputs.size() * sizeof(glm::vec4)), inputs.data(),
                 GL_STATIC_DRAW);
    std::vector<glm::vec4> outputs(2 * inputs.size());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, buffers[1]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(outputs.size() * sizeof(glm::vec4)), nullptr,
                 GL_DYNAMIC_READ);
    glDispatchCompute(GLuint((inputs.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(outputs.size() * sizeof(glm::vec4)), outputs.data());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    return outputs;
  }
  // |gpu - cpu| within `relative` of |cpu| (and of 1e-30, for the exact zeros outside a cone).
  static bool agree(double gpu, double cpu, double relative) {
    return std::abs(gpu - cpu) <= relative * std::max(std::abs(cpu), 1e-30);
  }

  testing::EglContext gl;
  gl::Program program;
  GLuint buffers[2] = {};
};

TEST_F(ShaderAgreement, FresnelTransmittanceOverAnglesAndEta) {
  std::vector<glm::vec4> inputs;
  for (float eta : {1.0f, 1.1f, 1.3f, 1.33f, 1.44f, 1.5f, 2.0f, 2.5f})
    for (int k = 0; k <= 128; ++k) inputs.emplace_back(eta, float(k) / 128.0f, 0.0f, 0.0f);
  std::vector<glm::vec4> gpu = evaluate(inputs, true);
  int compared = 0;
  for (size_t i = 0; i < inputs.size(); ++i) {
    double cpu = fresnelTransmittance(double(inputs[i].x), double(inputs[i].y));
    EXPECT_PRED3(agree, gpu[2 * i].x, cpu, 1e-5) << "eta " << inputs[i].x << ", cos theta " << inputs[i].y;
    ++compared;
  }
  EXPECT_EQ(compared, 8 * 129);
}

// Surface points around the light: a grid of 9 x 9 x 5 points of the box [-2, 2]^2 x [-1, 1].
std::vector<glm::vec4> surfacePoints() {
  std::vector<glm::vec4> points;
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 9; ++x)
        points.emplace_back(-2.0f + 0.5f * float(x), -2.0f + 0.5f * float(y), -1.0f + 0.5f * float(z), 1.0f);
  return points;
}

// How far float evaluations of one cosine (normalize, dot) may differ: 4 ulps of 1.
constexpr double kCosineRounding = 4.0 * 1.19e-7;

SsLightDesc light(int32_t type) {
  SsLightDesc l{};
  l.type = type;
  l.color[0] = 1.0f, l.color[1] = 0.6f, l.color[2] = 0.25f;
  l.strength = type == SS_LIGHT_SUN ? 3.5f : 250.0f;
  l.position[0] = 0.3f, l.position[1] = -0.2f, l.position[2] = 3.0f;
  glm::vec3 direction = glm::vec3(0.2f, 0.1f, -1.0f);  // not unit: the library normalises it
  l.direction[0] = direction.x, l.direction[1] = direction.y, l.direction[2] = direction.z;
  l.spot_size = float(M_PI) * 75.0f / 180.0f;
  l.spot_blend = 0.4f;
  return l;
}

// Each light type: the direction towards the light and the irradiance on a surface facing it
// (the inverse square falloff, the spot's cone and its smooth blend), GPU against REFERENCE's.
TEST_F(ShaderAgreement, LightDirectionAndIrradianceOfEveryLightType) {
  const std::vector<glm::vec4> points = surfacePoints();
  for (int32_t type : {SS_LIGHT_POINT, SS_LIGHT_SPOT, SS_LIGHT_SUN}) {
    const SsLightDesc l = light(type);
    LightView view;
    view.light = &l;
    glUseProgram(program.id());
    setLightUniforms(program.id(), view);  // as the passes set them
    std::vector<glm::vec4> gpu = evaluate(points, false);
    int lit = 0, dark = 0, blended = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      glm::vec3 p(points[i]);
      LightSample cpu = sampleLight(l, p);
      double relative = 1e-5;
      if (type == SS_LIGHT_SPOT) {
        // Away from the cone's edge, where a last-bit difference in the cosine to the axis
        // decides between dark and a smoothstep of almost nothing.
        float cosHalf = std::cos(0.5f * l.spot_size), smooth = (1.0f - cosHalf) * l.spot_blend;
        float c = glm::dot(-cpu.towardsLight, glm::normalize(glm::vec3(l.direction[0], l.direction[1], l.direction[2])));
        if (std::abs(c - cosHalf) < 0.02f * smooth) continue;
        if (c > cosHalf && c - cosHalf < smooth) {
          // In the blend, E = E0 c s(x), x = (c - cos half) / smooth, s = smoothstep: a rounding
          // of c by dc (float normalize and dot, a few ulps) moves E by dE / E =
          // dc (1 / c + s'(x) / (s(x) smooth)), more than 1e-5 where x is small.
          double x = (double(c) - cosHalf) / smooth, s = x * x * (3.0 - 2.0 * x), ds = 6.0 * x * (1.0 - x);
          relative = 1e-5 + kCosineRounding * (1.0 / c + ds / (s * smooth));
          ++blended;
        }
      }
      (cpu.irradiance.x > 0.0f ? lit : dark) += 1;
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(gpu[2 * i][k], cpu.towardsLight[k], 1e-5) << "light type " << type << ", point " << i;
        EXPECT_PRED3(agree, gpu[2 * i + 1][k], cpu.irradiance[k], relative) << "light type " << type << ", point " << i;
      }
    }
    EXPECT_GT(lit, 0) << "light type " << type;
    if (type == SS_LIGHT_SPOT) {
      EXPECT_GT(dark, 0) << "no point outside the cone";
      EXPECT_GT(blended, 0) << "no point in the blend region";
    }
  }
}

}  // namespace
}  // namespace subsplat
