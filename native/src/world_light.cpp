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

}  // namespace

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
    if (l.type == SS_LIGHT_WORLD)
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
  out.worldRadiance = radiance;
  out.worldBelow = below;
  if (radiance == glm::vec3(0.0f) && below == glm::vec3(0.0f)) return out;
  Bounds translucent = scene.bounds(true);
  int count = world->world_directions != 0
                  ? world->world_directions
                  : automaticWorldDirections(scene.lights(), translucent.empty() ? scene.bounds(false) : translucent);
  if (count < 0) {
    out.unshadowed = true;
    return out;
  }
  out.worldDirections = worldDirections(count);
  for (const glm::vec3& w : out.worldDirections) {
    SsLightDesc sun{};
    sun.type = SS_LIGHT_SUN;
    glm::vec3 l = w.z >= 0.0f ? radiance : below;
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
