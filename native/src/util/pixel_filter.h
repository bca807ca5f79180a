// Anti-aliasing (docs/ANTIALIASING.md): where in the pixel each jittered sample of a frame looks,
// and the camera that looks there.
#pragma once

#include <glm/glm.hpp>

#include "subsplat/subsplat.h"

namespace subsplat {

// The offset of sample `index` from the pixel's centre, in pixels. Sample 0 is the centre; then
// pairs of a point and its mirror through the centre, the points a 2D low-discrepancy sequence
// (Roberts' R2) mapped through the inverse of the Blackman-Harris filter's CDF on each axis, as
// Cycles importance-samples Blender's pixel filter (its support is twice Blender's Filter Size,
// `filterWidth`). Equal weights then give the filtered image.
glm::vec2 pixelFilterOffset(int index, float filterWidth);
// Blackman-Harris of support [-width, width] (Cycles' filter_func_blackman_harris with its
// width doubled), unnormalised; its CDF on the same support.
double blackmanHarris(double x, double filterWidth);
double blackmanHarrisCdf(double x, double filterWidth);
// `camera` with its image shifted by `offset` pixels in a width x height frame: the surface at
// the pixel's centre is the one `offset` away in the original frame.
SsCameraDesc jitteredCamera(const SsCameraDesc& camera, glm::vec2 offset, int width, int height);

}  // namespace subsplat
