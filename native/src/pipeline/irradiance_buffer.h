// The irradiance buffer (paper sec. 4, step 1): the lit surface seen from a
// light view, texel by texel (position, flux and footprint, normal, depth),
// and its hierarchy of coarser levels for sample selection.
#pragma once

#include "gl/gl.h"
#include "pipeline/light_views.h"
#include "pipeline/pass_helpers.h"
#include "scene.h"

namespace subsplat {

// What the direct-lighting pass reads of a light view: the irradiance buffer's light depth (soft
// shadows), position and normal (TABULATED materials' light through thin parts), level 0, and the
// shadow map of the hard shadows (pipeline/shadow_map.h; the irradiance buffer's light depth when
// it has the same resolution).
// softDepth: the map at the irradiance buffer's resolution that point, spot and area lights' soft
// shadows filter (0: lightDepth; a shadow map when the irradiance buffer was drawn without opaque
// surfaces, SoftEntries).
struct ShadowInputs {
  GLuint lightDepth = 0, positionMaterial = 0, normalObject = 0;
  int resolution = 0;
  GLuint shadowDepth = 0;
  int shadowResolution = 0;
  GLuint softDepth = 0;
};

// Soft shadows on the light entering translucent objects (docs/SOFT_SHADOWS.md): the irradiance
// buffer is drawn without opaque surfaces, and each translucent texel's flux is scaled by the share
// of the light reaching it past other objects, filtered on `map` (a ShadowMap of every surface, of
// `resolution` texels, drawn before). map 0: off, every surface drawn and the depth test shadows.
struct SoftEntries {
  GLuint map = 0;
  int resolution = 0;
  bool on() const { return map != 0; }
};

class IrradianceBuffer {
 public:
  // levels: 1 for BRUTE; the hierarchy's depth for the adaptive methods.
  // profileSplits: keep, per level-0 texel, where a second profile covers part
  // of it (heterogeneous scenes only; docs/HETEROGENEOUS.md).
  void resize(int resolution, int levels = 1, bool profileSplits = false);
  void render(const Scene& scene, const GpuScene& gpu, const LightView& view, const SoftEntries& soft = {});
  // Only where the light enters each texel (positionMaterial, normalObject, lightDepth; no flux):
  // what PRECOMPUTED's direct light reads of a view with TABULATED materials (entry_points.frag).
  void renderEntries(const Scene& scene, const GpuScene& gpu, const LightView& view, const SoftEntries& soft = {});
  // TABULATED materials (material/transport_model.h): renders where the light leaves each part
  // (exitDepth) and scales the finest level's flux by the incidence factor R(tau, mu0) / R(1).
  // Before buildHierarchy; transportTables: MaterialTables::transport().
  // translucentOnly: the buffer was drawn with SoftEntries (opaque surfaces are no exits either).
  void applyIncidence(const Scene& scene, const GpuScene& gpu, const LightView& view, GLuint transportTables,
                      bool translucentOnly = false);
  // Builds levels 1 .. levels-1 and the min/max depth hierarchy from level 0.
  void buildHierarchy();
  int resolution() const { return resolution_; }
  int levels() const { return levels_; }
  // rg: min and max light depth under each texel, levels 1 .. levels-1
  // (level 0 is lightDepth()).
  GLuint depthRange() const { return depthRange_.id(); }
  GLuint positionMaterial() const { return positionMaterial_.id(); }
  GLuint fluxFootprint() const { return fluxFootprint_.id(); }
  GLuint normalObject() const { return normalObject_.id(); }
  // r: light depth, g: the share of the light that reaches the texel (1 unless SoftEntries).
  GLuint lightDepth() const { return lightDepth_.id(); }
  ShadowInputs shadowInputs() const {
    return {lightDepth_.id(), positionMaterial_.id(), normalObject_.id(), resolution_, lightDepth_.id(), resolution_};
  }
  // r: light depth of the nearest surface facing away from the light, g: its object index, ba: its
  // normal (octahedral)
  // (applyIncidence; empty until it ran at this size).
  GLuint exitDepth() const { return exitDepth_.id(); }
  // Every level, 0 unless resized with profileSplits: xyz the offset of the
  // second profile's part from the texel centre over the footprint sigma,
  // w = (its entry - the material's first) * 32 + its sixteenths of the texel.
  GLuint profileSplit() const { return profileSplit_.id(); }
  bool profileSplits() const { return profileSplits_; }

 private:
  int resolution_ = 0, levels_ = 0;
  bool profileSplits_ = false;
  gl::ProgramVariants programs_{"mesh.vert", "", "irradiance_buffer.frag"};  // the scene's, SOFT_ENTRIES, AREA_LIGHT
  gl::Program entryProgram_, reduceProgram_, exitProgram_, incidenceProgram_;
  gl::Texture positionMaterial_, fluxFootprint_, normalObject_, lightDepth_, depthRange_, depth_, profileSplit_;
  gl::Texture exitDepth_, exitZ_;
  gl::Framebuffer framebuffer_, exitFramebuffer_;
};

}  // namespace subsplat
