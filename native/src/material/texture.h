// Images that materials read through their meshes' UVs (docs/TEXTURES.md): the CPU's copy and
// look-up, which REFERENCE uses and the shaders repeat (common.glsl: textureRgb).
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <vector>

#include "subsplat/subsplat.h"

namespace subsplat {

// An image as ssNewImage took it: scene-linear RGB, row 0 at v = 0. Immutable.
class TextureImage {
 public:
  static constexpr uint32_t kMaxSide = 16384;
  // Validates the description (sizes, finite values in [0, 1e4]) and copies the texels.
  explicit TextureImage(const SsImageDesc& desc);
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<glm::vec3>& texels() const { return texels_; }
  glm::vec3 texel(int x, int y) const { return texels_[size_t(y) * size_t(width_) + size_t(x)]; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<glm::vec3> texels_;
};

// A material's use of an image: its UV transform, extension and interpolation.
struct Texture {
  std::shared_ptr<const TextureImage> image;  // null: none
  float transform[6] = {1, 0, 0, 0, 1, 0};
  int32_t extension = SS_TEXTURE_REPEAT;
  int32_t interpolation = SS_TEXTURE_LINEAR;

  explicit operator bool() const { return bool(image); }
  // The desc's fields (its image is the caller's to resolve); all-zero transform: the identity.
  static Texture fromDesc(const SsTextureDesc& desc, std::shared_ptr<const TextureImage> image);
  glm::vec2 mapped(glm::vec2 uv) const {
    return {transform[0] * uv.x + transform[1] * uv.y + transform[2], transform[3] * uv.x + transform[4] * uv.y + transform[5]};
  }
  // The image at the mesh's uv: bilinear between texel centres (or the nearest texel), repeated,
  // extended or black outside [0, 1].
  glm::vec3 sample(glm::vec2 uv) const;
};

// The environment drawn where no object is (SsEnvironmentDesc): an equirectangular image, Blender's
// convention, turned by `rotation`, times `strength`. The shaders repeat radiance()
// (final_shading.frag: environmentRadiance).
struct Environment {
  std::shared_ptr<const TextureImage> image;  // null: none
  glm::mat3 rotation{1.0f};
  float strength = 1.0f;
  explicit operator bool() const { return bool(image); }
  // Validates the desc's fields other than its image.
  static Environment fromDesc(const SsEnvironmentDesc& desc, std::shared_ptr<const TextureImage> image);
  // The image's (u, v) for a world direction (not necessarily unit).
  glm::vec2 uv(const glm::vec3& direction) const;
  // Radiance along a world direction: bilinear, repeating in u and clamped in v.
  glm::vec3 radiance(const glm::vec3& direction) const;
};

// Checks a texture description's fields other than its image: a finite transform and known modes.
void validateTexture(const SsTextureDesc& desc, const char* what);

// The shading normal from a tangent-space normal map: rgb in [0, 1] as 0.5 (n + 1) in the frame
// (tangent, bitangent, normal), tilted by `strength` as Blender's Normal Map node (mix of the mesh's
// normal and the map's by strength, renormalised).
glm::vec3 perturbedNormal(const glm::vec3& rgb, float strength, const glm::vec3& normal, const glm::vec3& tangent,
                          const glm::vec3& bitangent);

// A triangle's tangent and bitangent (dP/du, dP/dv) from its corners' positions and UVs; zero
// vectors when its UVs are degenerate (the normal map then leaves the normal as it is).
void triangleTangents(const glm::vec3 p[3], const glm::vec2 uv[3], glm::vec3& tangent, glm::vec3& bitangent);

}  // namespace subsplat
