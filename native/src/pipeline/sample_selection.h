// Sample selection (paper sec. 4, Algorithm 1): which irradiance samples are
// splatted, decided once per light view from the irradiance hierarchy
// (select_samples.comp) into the list every splatting draw of the view reads
// (splat.vert); here its parameters, uniforms and list.
#pragma once

#include "gl/gl.h"
#include "pipeline/irradiance_buffer.h"
#include "pipeline/light_views.h"
#include "pipeline/splatting_buffer.h"
#include "scene.h"

namespace subsplat {

// Which irradiance samples are splatted: levels == 1 takes every finest texel
// (BRUTE); more levels select adaptively (Algorithm 1, select_samples.comp).
struct Selection {
  int levels = 1;
  float z0 = 0.0f;     // depth-range threshold, scene units
  float alpha = 15.0f;
  // The TABULATED model's forward shift (SsSettings::forward_shift): the splat program's, not
  // MATERIAL_EDIT's transport (splat.vert's forwardShifts).
  bool forwardShift = true;
};

// The samples select_samples.comp selects per irradiance level (STORAGE_SELECTION_COUNTS), summed over a
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

// The samples of one light view that are splatted, in the order of the hierarchy's texels
// (select_samples.comp). Splatting's draws were one vertex per texel of every level, each running
// Algorithm 1 again, for every splatting level: on llvmpipe up to two thirds of FULL's frame
// went to vertices that drew nothing (docs/BENCHMARKS.md, "Selection once per light view"). The list is
// made once per view and drawn by every level, with glDrawArraysIndirect or a range of it.
class SampleList {
 public:
  // Selects the view's samples; adds them per level to counts where given. Leaves the selection's
  // uniforms and textures bound as setSelectionUniforms does, for the draws' program to set again.
  void build(const Scene& scene, const LightView& view, const IrradianceBuffer& irradiance,
             const SplattingBuffer& splatting, const Selection& selection, SelectionCounts* counts);
  // Binds the list at STORAGE_SAMPLE_LIST and GL_DRAW_INDIRECT_BUFFER.
  void bind() const;
  // Draws the whole list as points (the bound program's vertex shader reads it).
  void draw() const;
  // The number of samples listed (a read-back: for drawing ranges of the list).
  GLint count() const;
  // select_samples.comp's workgroup: invocations, samples an invocation, samples a workgroup.
  static constexpr size_t kGroupInvocations = 64, kChunk = 16, kGroupSamples = kGroupInvocations * kChunk;

 private:
  gl::Program program_;
  gl::Buffer list_, ranks_, blocks_;  // list_: the indirect command, then the samples; ranks_: a
                                      // uint an invocation; blocks_: a uint a workgroup
  size_t capacity_ = 0;               // samples the buffers hold
};

}  // namespace subsplat
