// Sample selection (paper sec. 4, Algorithm 1): which irradiance samples are
// splatted, decided per sample in splat.vert from the irradiance hierarchy;
// here its parameters and uniforms.
#pragma once

#include "gl/gl.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/light_views.h"
#include "pipeline/splatting_buffer.h"
#include "scene.h"

namespace subsplat {

// Which irradiance samples are splatted: levels == 1 takes every finest texel
// (BRUTE); more levels select adaptively (Algorithm 1, splat.vert).
struct Selection {
  int levels = 1;
  float z0 = 0.0f;     // depth-range threshold, scene units
  float alpha = 15.0f;
};

// The samples splat.vert selects per irradiance level (STORAGE_SELECTION_COUNTS), summed over a
// frame's light views; read back once a frame.
class SelectionCounts {
 public:
  void clear();       // zeroes them (the buffer is made on first use)
  void bind() const;  // at STORAGE_SELECTION_COUNTS
  // Adds them to selectedPerLevel; returns their sum.
  uint64_t read(uint64_t selectedPerLevel[8]);

 private:
  gl::Buffer buffer_;
};

// The selection's uniforms and the irradiance and splatting buffers it reads;
// offsets: where each irradiance level's samples start (9 entries).
void setSelectionUniforms(GLuint program, const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
                          const SplattingBuffer& splatting, const Selection& selection, GLint offsets[9]);

}  // namespace subsplat
