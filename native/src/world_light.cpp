#include "world_light.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

#include "material/dipole.h"
#include "material/transport_model.h"
#include "reference/lighting.h"

namespace subsplat {

namespace {

float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

bool hasHarmonics(const SsLightDesc& l) {
  for (float v : l.world_sh)
    if (v != 0.0f) return true;
  return false;
}

}  // namespace

std::array<float, 9> sphericalHarmonics(const glm::vec3& d) {
  float x = d.x, y = d.y, z = d.z;
  return {0.28209479f,          0.48860251f * y,           0.48860251f * z,
          0.48860251f * x,      1.09254843f * x * y,       1.09254843f * y * z,
          0.31539157f * (3.0f * z * z - 1.0f), 1.09254843f * x * z, 0.54627422f * (x * x - y * y)};
}

glm::vec3 worldRemainder(const RenderLights& lights, const glm::vec3& d) {
  if (!lights.worldHarmonics) return worldHemisphereMix(lights.worldRadiance, lights.worldBelow, d.z);
  std::array<float, 9> y = sphericalHarmonics(d);
  glm::vec3 e(0.0f);
  for (int i = 0; i < 9; ++i) e += lights.worldIrradiance[size_t(i)] * y[size_t(i)];
  return glm::max(e, glm::vec3(0.0f));
}

std::vector<glm::vec3> worldDirections(int count) {
  std::vector<glm::vec3> directions;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    double z = 1.0 - (2.0 * i + 1.0) / count, r = std::sqrt(std::max(1.0 - z * z, 0.0)), phi = golden * i;
    directions.emplace_back(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
  }
  return directions;
}

int automaticWorldDirections(const std::vector<SsLightDesc>& lights, const Bounds& fit) {
  glm::vec3 centre = fit.empty() ? glm::vec3(0.0f) : fit.center();
  double world = 0.0, others = 0.0;
  for (const SsLightDesc& l : lights) {
    if (l.type == SS_LIGHT_WORLD && hasHarmonics(l))
      world += M_PI * luminance(glm::make_vec3(l.world_sh) * 0.28209479f);  // the mean radiance
    else if (l.type == SS_LIGHT_WORLD)
      world += M_PI * luminance(0.5f * (glm::make_vec3(l.color) * l.strength + glm::make_vec3(l.world_below)));
    else
      others += luminance(sampleLight(l, centre).irradiance);
  }
  double share = world > 0.0 ? world / (world + others) : 0.0;
  return share < 0.1 ? -1 : share < 0.5 ? 8 : 16;
}

RenderLights renderLights(const Scene& scene) {
  RenderLights out;
  const SsLightDesc* world = nullptr;
  for (const SsLightDesc& l : scene.lights()) {
    if (l.type == SS_LIGHT_WORLD) {
      world = &l;
      continue;
    }
    out.lights.push_back(l);
    out.world.push_back(false);
  }
  if (!world) return out;
  glm::vec3 radiance = glm::make_vec3(world->color) * world->strength, below = glm::make_vec3(world->world_below);
  std::array<glm::vec3, 9> harmonics{};  // the radiance's coefficients
  if (hasHarmonics(*world)) {
    // A surface facing up or down under the harmonics stands for the two halves (the specular
    // remainder's fallback and the K directions' scale below).
    out.worldHarmonics = true;
    const float band[9] = {1.0f, 2.0f / 3, 2.0f / 3, 2.0f / 3, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
    for (int i = 0; i < 9; ++i) {
      harmonics[size_t(i)] = glm::make_vec3(world->world_sh + 3 * i);
      out.worldIrradiance[size_t(i)] = harmonics[size_t(i)] * band[i];
    }
    radiance = worldRemainder(out, glm::vec3(0, 0, 1));
    below = worldRemainder(out, glm::vec3(0, 0, -1));
  }
  out.worldRadiance = radiance;
  out.worldBelow = below;
  if (radiance == glm::vec3(0.0f) && below == glm::vec3(0.0f) && !out.worldHarmonics) return out;
  Bounds translucent = scene.bounds(true);
  int count = world->world_directions != 0
                  ? world->world_directions
                  : automaticWorldDirections(scene.lights(), translucent.empty() ? scene.bounds(false) : translucent);
  if (count < 0) {
    out.unshadowed = true;
    return out;
  }
  out.worldDirections = worldDirections(count);
  // Each direction's radiance: the half's (two halves), or the harmonics' radiance there, clamped at
  // 0. An unoccluded surface gets pi times the cosine-weighted mean of the directions it faces:
  // exactly a half's for two halves. For harmonics, K directions come near the irradiance (for a
  // radiance a + b . w the continuous mean is a + 2/3 b . n, theirs), and each half is scaled so
  // that surfaces facing up and down get it exactly, as for two halves; the scale is kept within
  // [1/2, 2], a guard for a half where the clamped radiance is nearly all cut.
  std::vector<glm::vec3> colours;
  glm::vec3 sums[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
  float cosines[2] = {0.0f, 0.0f};
  for (const glm::vec3& w : out.worldDirections) {
    glm::vec3 l = w.z >= 0.0f ? radiance : below;
    if (out.worldHarmonics) {
      std::array<float, 9> y = sphericalHarmonics(w);
      l = glm::vec3(0.0f);
      for (int i = 0; i < 9; ++i) l += harmonics[size_t(i)] * y[size_t(i)];
      l = glm::max(l, glm::vec3(0.0f));
    }
    colours.push_back(l);
    int half = w.z >= 0.0f ? 0 : 1;
    sums[half] += l * std::abs(w.z);
    cosines[half] += std::abs(w.z);
  }
  glm::vec3 scale[2] = {glm::vec3(1.0f), glm::vec3(1.0f)};
  for (int half = 0; out.worldHarmonics && half < 2; ++half)
    for (int c = 0; c < 3; ++c) {
      float target = half == 0 ? radiance[c] : below[c];                      // E / pi facing up (down)
      float got = cosines[half] > 0.0f ? sums[half][c] / cosines[half] : 0.0f;  // what the directions give
      if (got > 0.0f && target > 0.0f) scale[half][c] = std::clamp(target / got, 0.5f, 2.0f);
    }
  for (size_t k = 0; k < out.worldDirections.size(); ++k) {
    const glm::vec3& w = out.worldDirections[k];
    glm::vec3 l = colours[k] * scale[w.z >= 0.0f ? 0 : 1];
    SsLightDesc sun{};
    sun.type = SS_LIGHT_SUN;
    for (int c = 0; c < 3; ++c) sun.color[c] = l[c], sun.direction[c] = -w[c];
    sun.strength = 1.0f;
    out.lights.push_back(sun);
    out.world.push_back(true);
  }
  return out;
}

glm::vec3 worldHemisphereMix(const glm::vec3& above, const glm::vec3& below, float z) {
  float up = 0.5f * (1.0f + std::clamp(z, -1.0f, 1.0f));
  return up * above + (1.0f - up) * below;
}

float worldWeight(const std::vector<glm::vec3>& directions, const glm::vec3& n) {
  float d = 0.0f;
  for (const glm::vec3& w : directions) d += std::max(glm::dot(n, w), 0.0f);
  return float(M_PI) / std::max(d, 1e-3f);
}

float specularAlbedo(float roughness, float specular, float cosView) {
  // Karis, "Physically Based Shading on Mobile" (2014): the split-sum's DFG term, fitted.
  float f0 = 0.08f * specular;
  if (f0 <= 0.0f) return 0.0f;
  float r = std::clamp(roughness, 0.02f, 1.0f);
  glm::vec4 c = r * glm::vec4(-1.0f, -0.0275f, -0.572f, 0.022f) + glm::vec4(1.0f, 0.0425f, 1.04f, -0.04f);
  float a004 = std::min(c.x * c.x, std::exp2(-9.28f * std::clamp(cosView, 0.0f, 1.0f))) * c.x + c.y;
  return f0 * (-1.04f * a004 + c.z) + (1.04f * a004 + c.w);
}

double diffuseTransmittance(double eta) {
  constexpr int kSteps = 256;  // midpoint rule in mu^2 (the integrand is smooth in it)
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i) sum += fresnelTransmittance(eta, std::sqrt((i + 0.5) / kSteps));
  return sum / kSteps;
}

glm::vec3 unshadowedResponse(const MaterialEntry& entry) {
  if (!entry.kernel) return glm::vec3(0.0f);
  double mean = diffuseTransmittance(entry.desc.eta);
  glm::vec3 response(0.0f);
  for (int c = 0; c < 3; ++c) {
    double total = entry.kernel->totalReflectance()[size_t(c)];
    if (entry.transport) {
      double r1 = halfSpaceAlbedoAtNormalIncidence(entry.transport->albedo()[size_t(c)]);
      total = r1 > 0.0 ? total / r1 : 0.0;
    }
    response[c] = float(total * mean);
  }
  return response;
}

}  // namespace subsplat
