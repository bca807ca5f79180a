// Accumulation (paper sec. 4, eq. 17): the splatting levels'
// exitance gathered into the finest, coarse to fine, weighted by depth and
// normal agreement. Splatting::accumulate (accumulation.cpp) does it.
#pragma once

#include "gl/gl.h"
#include "pipeline/splatting_buffer.h"
#include "scene.h"

namespace subsplat {

// Eq. 17's weights.
struct Accumulation {
  float lambdaZ = 8.0f, lambdaM = 8.0f;
  float boundingDiameter = 1.0f;  // R_w
};

// The start of an accumulation pass with program p (fullscreen.vert, accumulate.frag): eq. 17's
// weights, the splatting buffer it reads, additive blending. transportLayers: 0 for the exitance
// (UNIT_COARSE_EXITANCE), else the layers of a coarse level's array (UNIT_COARSE_TRANSPORT).
void beginAccumulation(GLuint p, const Scene& scene, const SplattingBuffer& splatting, const Accumulation& weights,
                       int transportLayers);

}  // namespace subsplat
