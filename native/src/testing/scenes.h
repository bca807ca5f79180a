// Small scenes built through the C API, shared by native tests and tools.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "subsplat/subsplat.h"

namespace subsplat::testing {

struct Quad {
  std::vector<float> positions{-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  std::vector<float> normals{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  std::vector<uint32_t> indices{0, 1, 2, 0, 2, 3};
  SsMeshDesc desc(float halfSize, uint32_t material) const;
};

SsMaterialDesc marbleMaterial(float mmPerUnit);
// Orthographic camera looking down -z at the origin from z = 5.
SsCameraDesc topDownCamera(float halfWidth);
SsLightDesc sunLight(float strength, float incidenceDegrees);

}  // namespace subsplat::testing
