// The views an irradiance buffer is rendered from: an orthographic frustum
// fitted to the translucent objects for a sun, the six faces of a cube for a
// point light, one perspective frustum (or a cube for wide cones) for a spot,
// five faces of a cube in its own frame for an area light.
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
  // Soft shadows (direct_lighting.frag): sun: tan of half its angle; point, spot: its radius; area:
  // the radius of the disk of its area (non-zero: soft; its shape is softAxes); 0: hard. nearDepth: the least light depth of any
  // object in the view, the farthest a blocker can be from a receiver.
  float softSize = 0.0f;
  float nearDepth = 0.0f;
  // An area light's shape, for its soft shadows: its semi-axes in the world (zero for other lights,
  // whose disk faces each receiver) and whether it is a rectangle (else an ellipse).
  glm::vec3 softAxes[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};
  bool softRectangle = false;
};

// LightView::softSize of every view of `light`.
float lightSoftSize(const SsLightDesc& light);
// An area light's semi-axes in the world (along area_axis, then across it), and whether it is a
// rectangle (square, rectangle) or an ellipse (disk, ellipse).
void areaSemiAxes(const SsLightDesc& light, glm::vec3& a, glm::vec3& b, bool& rectangle);

std::vector<LightView> lightViews(const SsLightDesc& light, const Bounds& translucent,
                                  const Bounds& all, int resolution);

}  // namespace subsplat
