// The lights and the surface terms of the GPU shaders (common.glsl,
// direct_lighting.frag), on the CPU for REFERENCE: the same radiometry, so
// that REFERENCE and the real-time methods differ only in how they sum eq. 5.
#pragma once

#include <glm/glm.hpp>

#include "subsplat/subsplat.h"

namespace subsplat {

struct LightSample {
  glm::vec3 towardsLight{0.0f};  // unit
  float distance = 0.0f;         // to the light; infinite for the sun
  glm::vec3 irradiance{0.0f};    // on a surface facing the light, W/m^2 (spot cone included)
};

// Cycles 3.x conventions (docs/DECISIONS.md): I = P / 4pi for point and spot.
LightSample sampleLight(const SsLightDesc& light, const glm::vec3& p);

// GGX specular with Schlick Fresnel, F0 = 0.08 specular, alpha = roughness^2,
// as direct_lighting.frag; n, l, v unit, n.l > 0.
float specularBrdf(const glm::vec3& n, const glm::vec3& l, const glm::vec3& v, float roughness, float specular);

}  // namespace subsplat
