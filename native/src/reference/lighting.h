// The lights and the surface terms of the GPU shaders (common.glsl,
// direct_lighting.frag), on the CPU for REFERENCE: the same radiometry, so
// that REFERENCE and the real-time methods differ only in how they sum eq. 5.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "subsplat/subsplat.h"

namespace subsplat {

struct LightSample {
  glm::vec3 towardsLight{0.0f};  // unit
  float distance = 0.0f;         // to the light; infinite for the sun
  glm::vec3 irradiance{0.0f};    // on a surface facing the light, W/m^2 (spot cone included)
};

// Cycles 3.x conventions (docs/DECISIONS.md): I = P / 4pi for point and spot. An area light's
// towardsLight is its centre's and its irradiance the one a surface facing the centre gets
// (areaIrradiance with n = towardsLight).
LightSample sampleLight(const SsLightDesc& light, const glm::vec3& p);

// sampleLight for a surface of normal n (either side: the side facing the light): for an area
// light, irradiance is the polygon's irradiance on that surface over its cosine to the centre, so
// that irradiance * max(0, n . towardsLight) is the surface's irradiance, as for every other light.
LightSample sampleLightOn(const SsLightDesc& light, const glm::vec3& p, const glm::vec3& n);

// An area light (SS_LIGHT_AREA; docs/AREA_LIGHTS.md): its corners in the world, counter-clockwise
// seen from the side it lights (a disk or an ellipse: a 16-gon of the same area), and its
// radiance per unit colour: P / (4 A), Cycles 3.x's convention (so it emits pi / 4 of P).
constexpr int kAreaDiskCorners = 16;
std::vector<glm::vec3> areaCorners(const SsLightDesc& light);
float areaRadiance(const SsLightDesc& light);
// The irradiance from a Lambertian polygon of unit radiance on a surface at p of normal n:
// Lambert's formula over the polygon clipped to n's hemisphere; 0 behind the emitter.
float polygonIrradiance(const std::vector<glm::vec3>& corners, const glm::vec3& emitterNormal,
                        const glm::vec3& p, const glm::vec3& n);

// GGX specular with Schlick Fresnel, F0 = 0.08 specular, alpha = roughness^2,
// as direct_lighting.frag; n, l, v unit, n.l > 0.
float specularBrdf(const glm::vec3& n, const glm::vec3& l, const glm::vec3& v, float roughness, float specular);

}  // namespace subsplat
