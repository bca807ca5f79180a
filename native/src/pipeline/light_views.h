// The views an irradiance buffer is rendered from: an orthographic frustum
// fitted to the translucent objects for a sun, the six faces of a cube for a
// point light, one perspective frustum (or a cube for wide cones) for a spot.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "scene.h"

namespace subsplat {

struct LightView {
  const SsLightDesc* light = nullptr;
  glm::mat4 viewProj{1.0f};
  float tanHalfFov = 1.0f;      // perspective: half-extent of the image plane at distance 1
  float orthoTexelArea = 0.0f;  // sun: texel area perpendicular to the light
  float shadowTexelSize = 0.0f; // sun: texel size; perspective: texel size at distance 1
  bool unshadowedOutside = false;
  // One of the world's shadowed directions (world_light.h): the world's whole direction set, for
  // D(n); nullptr for every other light.
  const std::vector<glm::vec3>* worldDirections = nullptr;
  // Soft shadows (direct_lighting.frag): sun: tan of half its angle; point, spot, area: its radius
  // (an area light's: the disk of its area); 0: hard. nearDepth: the least light depth of any
  // object in the view, the farthest a blocker can be from a receiver.
  float softSize = 0.0f;
  float nearDepth = 0.0f;
};

// LightView::softSize of every view of `light`.
float lightSoftSize(const SsLightDesc& light);

std::vector<LightView> lightViews(const SsLightDesc& light, const Bounds& translucent,
                                  const Bounds& all, int resolution);

}  // namespace subsplat
