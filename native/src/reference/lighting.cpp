#include "reference/lighting.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace subsplat {

std::vector<glm::vec3> areaCorners(const SsLightDesc& light) {
  glm::vec3 normal = glm::normalize(glm::make_vec3(light.direction));
  glm::vec3 x = glm::normalize(glm::make_vec3(light.area_axis));
  x = glm::normalize(x - normal * glm::dot(x, normal));
  glm::vec3 y = glm::cross(normal, x);  // x, y, normal right-handed: counter-clockwise seen from the front
  glm::vec3 centre = glm::make_vec3(light.position);
  bool twoSizes = light.area_shape == SS_AREA_RECTANGLE || light.area_shape == SS_AREA_ELLIPSE;
  float a = 0.5f * light.area_size[0], b = 0.5f * (twoSizes ? light.area_size[1] : light.area_size[0]);
  std::vector<glm::vec3> corners;
  if (light.area_shape == SS_AREA_SQUARE || light.area_shape == SS_AREA_RECTANGLE) {
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
      corners.push_back(centre + c.x * a * x + c.y * b * y);
    return corners;
  }
  // The 16-gon's radius scaled so that its area is the ellipse's.
  const double n = kAreaDiskCorners, scale = std::sqrt(M_PI / (0.5 * n * std::sin(2.0 * M_PI / n)));
  for (int k = 0; k < kAreaDiskCorners; ++k) {
    double phi = 2.0 * M_PI * k / n;
    corners.push_back(centre + float(scale * std::cos(phi)) * a * x + float(scale * std::sin(phi)) * b * y);
  }
  return corners;
}

float areaRadiance(const SsLightDesc& light) {
  bool twoSizes = light.area_shape == SS_AREA_RECTANGLE || light.area_shape == SS_AREA_ELLIPSE;
  double w = light.area_size[0], h = twoSizes ? light.area_size[1] : light.area_size[0];
  double area = light.area_shape == SS_AREA_DISK || light.area_shape == SS_AREA_ELLIPSE ? 0.25 * M_PI * w * h : w * h;
  return float(light.strength / (4.0 * area));  // Cycles 3.x (docs/AREA_LIGHTS.md)
}

float polygonIrradiance(const std::vector<glm::vec3>& corners, const glm::vec3& emitterNormal, const glm::vec3& p,
                        const glm::vec3& n) {
  if (corners.empty() || glm::dot(p - corners[0], emitterNormal) <= 0.0f) return 0.0f;  // behind the emitter
  std::vector<glm::dvec3> v;  // relative to p, clipped to n's hemisphere (Sutherland-Hodgman)
  glm::dvec3 dn(n);
  for (size_t i = 0; i < corners.size(); ++i) {
    glm::dvec3 a = glm::dvec3(corners[i]) - glm::dvec3(p), b = glm::dvec3(corners[(i + 1) % corners.size()]) - glm::dvec3(p);
    double da = glm::dot(dn, a), db = glm::dot(dn, b);
    if (da >= 0.0) v.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) v.push_back(a + (b - a) * (da / (da - db)));
  }
  double sum = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    glm::dvec3 a = v[i], b = v[(i + 1) % v.size()];
    if (glm::length(a) < 1e-12 || glm::length(b) < 1e-12) continue;
    a = glm::normalize(a), b = glm::normalize(b);
    glm::dvec3 c = glm::cross(a, b);
    double length = glm::length(c);
    if (length < 1e-12) continue;
    sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(dn, c / length);
  }
  return float(0.5 * std::abs(sum));
}

LightSample sampleLight(const SsLightDesc& light, const glm::vec3& p) {
  LightSample s;
  glm::vec3 color = glm::make_vec3(light.color);
  if (light.type == SS_LIGHT_AREA) {
    glm::vec3 d = glm::make_vec3(light.position) - p;
    s.distance = std::max(glm::length(d), 1e-10f);
    s.towardsLight = d / s.distance;
    s.irradiance = color * (areaRadiance(light) * polygonIrradiance(areaCorners(light), glm::normalize(glm::make_vec3(light.direction)), p, s.towardsLight));
    return s;
  }
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

LightSample sampleLightOn(const SsLightDesc& light, const glm::vec3& p, const glm::vec3& n) {
  LightSample s = sampleLight(light, p);
  if (light.type != SS_LIGHT_AREA) return s;
  glm::vec3 facing = glm::dot(n, s.towardsLight) >= 0.0f ? n : -n;
  float e = areaRadiance(light) *
            polygonIrradiance(areaCorners(light), glm::normalize(glm::make_vec3(light.direction)), p, facing);
  s.irradiance = glm::make_vec3(light.color) * (e / std::max(glm::dot(facing, s.towardsLight), 1e-3f));
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
