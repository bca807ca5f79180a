// The material tables the passes read: one MaterialGpu record per dense
// material entry, the splat kernel table of every translucent entry (one
// layer each), eq. 14's R-bar table and the textures' texels.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "gl/gl.h"
#include "scene.h"

namespace subsplat {

// The GPU layout of one entry (common.glsl: Material).
struct MaterialGpu {
  float baseColorKind[4];  // rgb base colour, w: 1 translucent, 0 opaque, -1 holdout
  float optics[4];
  float ranges[4];
  uint32_t profileMap[4];
  float medium[4];      // TABULATED: rgb single-scattering albedo, w: transport layer (-1: none)
  float extinction[4];  // TABULATED: rgb sigma_t per scene unit
  float world[4];       // translucent: rgb unshadowedResponse (world_light.h)
  uint32_t colorTexture[4];   // offset into the texels, width, height (0: none), extension | interpolation << 2
  float colorU[4], colorV[4];  // the UV transform's rows
  uint32_t normalTexture[4];
  float normalU[4], normalV[4];  // normalU[3]: strength
};

// The per-material tables the splat shaders read.
struct KernelTables {
  GLuint kernels = 0;        // 2D array: SplatKernel::table() per translucent material entry
  GLuint minimalRadius = 0;  // 2D: R-bar over log2 T, one row per layer
  int layers = 1;
  GLuint transport = 0;      // 2D array: TransportTables::texels() per TABULATED entry (at least one layer)
};

class MaterialTables {
 public:
  // Packs the scene's dense material entries (resolved) into the tables, again
  // only when the materials or epsilon (eq. 14) changed since the last call. Without
  // kernelTables, the splat kernels and R-bar are left as they were (a render that splats
  // nothing: MATERIAL_EDIT's edits), and the next call with them packs them.
  void update(const Scene& scene, float epsilon, bool kernelTables = true);
  // Shader storage: one MaterialGpu per dense entry.
  GLuint materials() const { return materialBuffer_.id(); }
  KernelTables kernels() const { return {kernelTable_.id(), minimalRadius_.id(), kernelLayers_, transport_.id()}; }
  GLuint transport() const { return transport_.id(); }
  // Every texture's image once, RGB32F texels one image after another (a buffer texture).
  GLuint textureTexels() const { return textureTexels_.id(); }

 private:
  // Every image the materials read, each once in the order met, into textureTexels_ (uploaded again
  // only when that list changes, not on every material edit); each image's first texel.
  std::map<const TextureImage*, uint32_t> uploadImages(const std::vector<MaterialEntry>& materials);

  gl::Buffer materialBuffer_, texelBuffer_;
  std::vector<std::shared_ptr<const TextureImage>> uploadedImages_;  // what textureTexels_ holds
  gl::Texture kernelTable_, minimalRadius_, transport_, textureTexels_;
  int kernelLayers_ = 1;
  float uploadedEpsilon_ = -1.0f;
  bool kernelTablesUploaded_ = false;
  uint64_t uploadedMaterialVersion_ = ~0ull;
};

}  // namespace subsplat
