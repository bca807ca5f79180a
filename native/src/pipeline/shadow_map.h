// A light view's shadow map at its own resolution (docs/SOFT_SHADOWS.md, "Shadow maps"): the light
// depth of the nearest surface and its object's index, for the hard shadows of the direct-lighting
// pass. The irradiance buffer's resolution follows the scattering; the shadow's staircase follows the
// image. A second map at the irradiance buffer's resolution serves the soft shadows on translucent
// objects (renderer.cpp, docs/SOFT_SHADOWS.md).
#pragma once

#include "gl/gl.h"
#include "pipeline/light_views.h"
#include "pipeline/pass_helpers.h"
#include "scene.h"

namespace subsplat {

class ShadowMap {
 public:
  void resize(int resolution);
  // The view's light depth at this map's resolution (the view's projection, every mesh).
  void render(const Scene& scene, const GpuScene& gpu, const LightView& view);
  int resolution() const { return resolution_; }
  // rg: light depth, object index.
  GLuint lightDepth() const { return lightDepth_.id(); }

 private:
  int resolution_ = 0;
  gl::Program program_;
  gl::Texture lightDepth_, depth_;
  gl::Framebuffer framebuffer_;
};

// The automatic shadow resolution (SsSettings.shadow_resolution): texels no larger than the image's
// pixels at the scene's centre (`all`'s) on the coarsest of `views` (made at `irradiance` texels),
// a power of two, at least `irradiance`, at most kMaxAutomatic.
constexpr int kMaxAutomaticShadowResolution = 2048;
int chooseShadowResolution(const Scene& scene, const std::vector<LightView>& views, const Bounds& all, int width,
                           int height, int irradiance, int maxTextureSize);

}  // namespace subsplat
