// Accumulation (paper sec. 4, eq. 17): the splatting levels'
// exitance gathered into the finest, coarse to fine, weighted by depth and
// normal agreement. Splatting::accumulate (accumulation.cpp) does it.
#pragma once

namespace subsplat {

// Eq. 17's weights.
struct Accumulation {
  float lambdaZ = 8.0f, lambdaM = 8.0f;
  float boundingDiameter = 1.0f;  // R_w
};

}  // namespace subsplat
