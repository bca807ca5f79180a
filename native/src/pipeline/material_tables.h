// The material tables the passes read: one MaterialGpu record per dense
// material entry, the splat kernel table of every translucent entry (one
// layer each) and eq. 14's R-bar table.
#pragma once

#include <cstdint>

namespace subsplat {

// The GPU layout of one entry (common.glsl: Material).
struct MaterialGpu {
  float baseColorKind[4];
  float optics[4];
  float ranges[4];
  uint32_t profileMap[4];
};

}  // namespace subsplat
