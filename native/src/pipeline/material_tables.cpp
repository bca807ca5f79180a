#include "pipeline/material_tables.h"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "material/splat_kernel.h"
#include "util/error.h"
#include "world_light.h"

namespace subsplat {

std::map<const TextureImage*, uint32_t> MaterialTables::uploadImages(const std::vector<MaterialEntry>& materials) {
  std::vector<std::shared_ptr<const TextureImage>> images;
  std::map<const TextureImage*, uint32_t> offsets;  // in texels
  size_t total = 0;
  for (const MaterialEntry& e : materials)
    for (const Texture* t : {&e.color, &e.normal})
      if (*t && offsets.try_emplace(t->image.get(), uint32_t(total)).second) {
        images.push_back(t->image);
        total += t->image->texels().size();
      }
  if (textureTexels_ && images == uploadedImages_) return offsets;  // a material edit that kept its images
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  if (total > size_t(std::max(maxTexels, 0)))
    fail(SS_LIMIT_EXCEEDED, "the materials' textures hold " + std::to_string(total) +
                                " texels, more than this GPU's buffer texture limit of " + std::to_string(maxTexels));
  std::vector<float> texels;
  texels.reserve(3 * std::max<size_t>(total, 1));
  for (const auto& image : images) {
    const float* first = &image->texels().front().x;
    texels.insert(texels.end(), first, first + 3 * image->texels().size());
  }
  if (texels.empty()) texels.assign(3, 1.0f);
  textureTexels_.reset();
  {
    gl::Purpose purpose("the materials' textures (" + std::to_string(texels.size() / 3) + " texels)");
    texelBuffer_ = gl::makeBuffer(GL_TEXTURE_BUFFER, texels.size() * sizeof(float), texels.data());
  }
  textureTexels_ = gl::makeBufferTexture(GL_RGB32F, texelBuffer_);
  uploadedImages_ = std::move(images);
  return offsets;
}

void MaterialTables::update(const Scene& scene, float epsilon, bool kernelTables) {
  if (uploadedMaterialVersion_ == scene.materialVersion() && materialBuffer_ && uploadedEpsilon_ == epsilon &&
      (kernelTablesUploaded_ || !kernelTables))
    return;
  const auto& materials = scene.denseMaterials();
  std::vector<MaterialGpu> gpu(std::max<size_t>(materials.size(), 1), MaterialGpu{});
  int layers = 0, transportLayers = 0;
  uint32_t mapOffset = 0;
  const std::map<const TextureImage*, uint32_t> imageOffsets = uploadImages(materials);
  auto place = [&](const Texture& t, uint32_t location[4], float rowU[4], float rowV[4]) {
    if (!t) return;
    location[0] = imageOffsets.at(t.image.get());
    location[1] = uint32_t(t.image->width());
    location[2] = uint32_t(t.image->height());
    location[3] = uint32_t(t.extension) | uint32_t(t.interpolation) << 2;
    for (int k = 0; k < 3; ++k) rowU[k] = t.transform[k], rowV[k] = t.transform[3 + k];
  };
  for (size_t i = 0; i < materials.size(); ++i) {
    const MaterialEntry& e = materials[i];
    const SsMaterialDesc& d = e.desc;
    MaterialGpu& g = gpu[i];
    // w: 1 translucent, 0 opaque, -1 holdout (common.glsl: isTranslucent, isHoldout).
    float kind = isTranslucent(d) ? 1.0f : d.kind == SS_MATERIAL_HOLDOUT ? -1.0f : 0.0f;
    g = MaterialGpu{};
    g.baseColorKind[0] = d.base_color[0], g.baseColorKind[1] = d.base_color[1], g.baseColorKind[2] = d.base_color[2];
    g.baseColorKind[3] = kind;
    g.optics[0] = d.eta, g.optics[1] = d.roughness, g.optics[2] = d.specular;
    g.profileMap[3] = uint32_t(e.base);
    g.medium[3] = -1.0f;
    g.colorU[0] = g.colorV[1] = g.normalU[0] = g.normalV[1] = 1.0f;  // no texture: the identity, unused
    place(e.color, g.colorTexture, g.colorU, g.colorV);
    place(e.normal, g.normalTexture, g.normalU, g.normalV);
    g.normalU[3] = d.normal_strength;
    glm::vec3 response = unshadowedResponse(e);
    for (int c = 0; c < 3; ++c) g.world[c] = response[c];
    if (e.mapped()) {
      g.profileMap[0] = mapOffset;
      g.profileMap[1] = uint32_t(e.profiles->width());
      g.profileMap[2] = uint32_t(e.profiles->height());
      if (i + 1 == materials.size() || materials[i + 1].base != e.base) mapOffset += uint32_t(e.profiles->map().size());
    }
    if (e.kernel) {
      const SplatKernel& k = *e.kernel;
      g.optics[3] = float(layers++);
      g.ranges[0] = float(k.supportRadius());
      g.ranges[1] = float(std::max({k.effectiveRange()[0], k.effectiveRange()[1], k.effectiveRange()[2]}));
      g.ranges[2] = float(std::min({k.effectiveRange()[0], k.effectiveRange()[1], k.effectiveRange()[2]}));
      g.ranges[3] = d.mm_per_unit;
    }
    if (e.transport) {
      const TransportTables& t = *e.transport;
      for (int c = 0; c < 3; ++c) {
        g.medium[c] = float(t.albedo()[size_t(c)]);
        g.extinction[c] = float(t.extinction()[size_t(c)] * d.mm_per_unit);
      }
      g.medium[3] = float(transportLayers++);
    }
  }
  materialBuffer_ = gl::makeBuffer(GL_SHADER_STORAGE_BUFFER, gpu.size() * sizeof(MaterialGpu), gpu.data());
  if (kernelTables) {
    kernelTable_ = gl::makeTexture2DArray(GL_RGBA32F, SplatKernel::kSizeD, SplatKernel::kSizeA,
                                          std::max(layers, 1), GL_LINEAR);
    for (size_t i = 0; i < materials.size(); ++i) {
      if (!materials[i].kernel) continue;
      glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, int(gpu[i].optics[3]), SplatKernel::kSizeD, SplatKernel::kSizeA, 1,
                      GL_RGBA, GL_FLOAT, materials[i].kernel->table().data());
    }
  }
  transport_ = gl::makeTexture2DArray(GL_RGBA32F, TransportTables::kWidth, TransportTables::height(),
                                      std::max(transportLayers, 1), GL_NEAREST);
  for (size_t i = 0; i < materials.size(); ++i) {
    if (!materials[i].transport) continue;
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, int(gpu[i].medium[3]), TransportTables::kWidth,
                    TransportTables::height(), 1, GL_RGBA, GL_FLOAT, materials[i].transport->texels().data());
  }
  if (kernelTables) {
    // Eq. 14's R-bar per layer, rebuilt only when materials or epsilon change:
    // over the mean normalised profile of the material's entries (eq. 15, 16),
    // weighted by how many texels of its map have each.
    std::vector<float> radii(size_t(SplatKernel::kRadiusTableSize) * std::max(layers, 1), 0.0f);
    for (size_t first = 0; first < materials.size();) {
      size_t end = first + 1;
      while (end < materials.size() && materials[end].base == materials[first].base) ++end;
      if (materials[first].kernel) {
        std::vector<std::pair<const SplatKernel*, double>> kernels;
        for (size_t i = first; i < end; ++i) {
          const MaterialEntry& e = materials[i];
          double weight = e.mapped() ? double(e.profiles->texelCounts()[i - first]) : 1.0;
          kernels.emplace_back(e.kernel.get(), weight);
        }
        std::vector<float> row = SplatKernel::minimalRadiusTable(kernels, epsilon);
        for (size_t i = first; i < end; ++i)
          std::copy(row.begin(), row.end(), radii.begin() + size_t(gpu[i].optics[3]) * SplatKernel::kRadiusTableSize);
      }
      first = end;
    }
    minimalRadius_ = gl::makeTexture2D(GL_R32F, SplatKernel::kRadiusTableSize, std::max(layers, 1), GL_LINEAR);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, SplatKernel::kRadiusTableSize, std::max(layers, 1), GL_RED, GL_FLOAT,
                    radii.data());
  }
  kernelLayers_ = std::max(layers, 1);
  gl::checkErrors("material upload");
  uploadedMaterialVersion_ = scene.materialVersion();
  uploadedEpsilon_ = epsilon;
  kernelTablesUploaded_ = kernelTables;
}

}  // namespace subsplat
