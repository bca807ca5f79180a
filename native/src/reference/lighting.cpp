#include "reference/lighting.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace subsplat {

LightSample sampleLight(const SsLightDesc& light, const glm::vec3& p) {
  LightSample s;
  glm::vec3 color = glm::make_vec3(light.color);
  if (light.type == SS_LIGHT_SUN) {
    s.towardsLight = -glm::normalize(glm::make_vec3(light.direction));
    s.distance = std::numeric_limits<float>::infinity();
    s.irradiance = color * light.strength;
    return s;
  }
  glm::vec3 d = glm::make_vec3(light.position) - p;
  float distance2 = std::max(glm::dot(d, d), 1e-20f);
  s.distance = std::sqrt(distance2);
  s.towardsLight = d / s.distance;
  s.irradiance = color * (light.strength / (4.0f * float(M_PI))) / distance2;
  if (light.type == SS_LIGHT_SPOT) {
    float cosHalf = std::cos(0.5f * light.spot_size);
    float smooth = (1.0f - cosHalf) * light.spot_blend;
    float c = glm::dot(-s.towardsLight, glm::normalize(glm::make_vec3(light.direction)));
    float attenuation = c <= cosHalf ? 0.0f : c;
    float t = c - cosHalf;
    if (attenuation > 0.0f && t < smooth && smooth > 0.0f) {
      float x = std::clamp(t / smooth, 0.0f, 1.0f);
      attenuation *= x * x * (3.0f - 2.0f * x);
    }
    s.irradiance *= attenuation;
  }
  return s;
}

float specularBrdf(const glm::vec3& n, const glm::vec3& l, const glm::vec3& v, float roughness, float specular) {
  float f0 = 0.08f * specular;
  if (f0 <= 0.0f) return 0.0f;
  float nl = glm::dot(n, l), nv = std::max(glm::dot(n, v), 1e-4f);
  glm::vec3 h = glm::normalize(l + v);
  float r = std::clamp(roughness, 0.02f, 1.0f);
  float alpha2 = r * r * r * r;
  float nh = std::max(glm::dot(n, h), 0.0f);
  float denom = nh * nh * (alpha2 - 1.0f) + 1.0f;
  float distribution = alpha2 / (float(M_PI) * denom * denom);
  auto g1 = [alpha2](float c) { return 2.0f * c / (c + std::sqrt(alpha2 + (1.0f - alpha2) * c * c)); };
  float fresnel = f0 + (1.0f - f0) * std::pow(1.0f - std::max(glm::dot(h, v), 0.0f), 5.0f);
  return distribution * g1(nl) * g1(nv) * fresnel / (4.0f * nl * nv);
}

}  // namespace subsplat
