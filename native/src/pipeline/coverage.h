// The frame's coverage figures (SsStats), counted on the GPU with atomic
// counters over the splatting buffer and the exitance (coverage.comp), so that
// a frame reads back its image and two counters, not two more RGBA32F images.
#pragma once

#include <cstdint>

#include "gl/gl.h"
#include "pipeline/splatting_buffer.h"

namespace subsplat {

struct CoverageCounts {
  uint64_t translucentPixels = 0;     // pixels showing a translucent material entry
  uint64_t litTranslucentPixels = 0;  // of those, with a finite exitance whose rgb sum is > 0
};

class Coverage {
 public:
  // Needs the material table bound at STORAGE_MATERIALS; materialCount: its entries.
  CoverageCounts count(const SplattingBuffer& splatting, GLuint exitance, int materialCount, int width, int height);

 private:
  gl::Program program_;
  gl::Buffer counts_;
};

}  // namespace subsplat
