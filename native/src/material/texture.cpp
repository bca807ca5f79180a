#include "material/texture.h"

#include <cmath>
#include <string>

#include "util/error.h"

namespace subsplat {

TextureImage::TextureImage(const SsImageDesc& desc) {
  require(desc.width >= 1 && desc.width <= kMaxSide && desc.height >= 1 && desc.height <= kMaxSide,
          "image size must be in [1, " + std::to_string(kMaxSide) + "] per side, got " + std::to_string(desc.width) +
              " x " + std::to_string(desc.height));
  require(desc.rgb != nullptr, "image rgb is NULL");
  width_ = int(desc.width);
  height_ = int(desc.height);
  size_t count = size_t(width_) * size_t(height_);
  texels_.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const float* v = desc.rgb + 3 * i;
    for (int c = 0; c < 3; ++c)
      if (!(std::isfinite(v[c]) && v[c] >= 0.0f && v[c] <= 1e4f))
        fail(SS_INVALID_ARGUMENT, "image texel (" + std::to_string(i % size_t(width_)) + ", " +
                                      std::to_string(i / size_t(width_)) + ") channel " + std::to_string(c) +
                                      " must be finite and in [0, 1e4], got " + std::to_string(v[c]));
    texels_[i] = {v[0], v[1], v[2]};
  }
}

void validateTexture(const SsTextureDesc& desc, const char* what) {
  for (float t : desc.transform)
    require(std::isfinite(t) && std::abs(t) <= 1e6f, std::string(what) + ": transform values must be finite and within 1e6");
  require(desc.extension >= SS_TEXTURE_REPEAT && desc.extension <= SS_TEXTURE_CLIP,
          std::string(what) + ": extension " + std::to_string(desc.extension) + " is not REPEAT, EXTEND or CLIP");
  require(desc.interpolation == SS_TEXTURE_LINEAR || desc.interpolation == SS_TEXTURE_CLOSEST,
          std::string(what) + ": interpolation " + std::to_string(desc.interpolation) + " is not LINEAR or CLOSEST");
}

Texture Texture::fromDesc(const SsTextureDesc& desc, std::shared_ptr<const TextureImage> image) {
  Texture t;
  t.image = std::move(image);
  bool zero = true;
  for (float v : desc.transform) zero = zero && v == 0.0f;
  if (!zero)
    for (int i = 0; i < 6; ++i) t.transform[i] = desc.transform[i];
  t.extension = desc.extension;
  t.interpolation = desc.interpolation;
  return t;
}

namespace {

// Texel index along one axis of n texels: wrapped (REPEAT) or clamped; -1 outside (CLIP).
int texelIndex(int i, int n, int extension) {
  if (extension == SS_TEXTURE_REPEAT) return ((i % n) + n) % n;
  if (extension == SS_TEXTURE_EXTEND) return std::min(std::max(i, 0), n - 1);
  return i < 0 || i >= n ? -1 : i;
}

}  // namespace

glm::vec3 Texture::sample(glm::vec2 uv) const {
  if (!image) return glm::vec3(1.0f);
  glm::vec2 m = mapped(uv);
  if (!(std::isfinite(m.x) && std::isfinite(m.y))) return glm::vec3(0.0f);
  if (extension == SS_TEXTURE_CLIP && (m.x < 0.0f || m.x > 1.0f || m.y < 0.0f || m.y > 1.0f)) return glm::vec3(0.0f);
  const int w = image->width(), h = image->height();
  // Large coordinates: REPEAT keeps the fraction (as the shader), others clamp.
  if (extension == SS_TEXTURE_REPEAT) m -= glm::floor(m);
  m = glm::clamp(m, glm::vec2(-1.0f), glm::vec2(2.0f));
  auto at = [&](int x, int y) {
    int tx = texelIndex(x, w, extension), ty = texelIndex(y, h, extension);
    return tx < 0 || ty < 0 ? glm::vec3(0.0f) : image->texel(tx, ty);
  };
  if (interpolation == SS_TEXTURE_CLOSEST)
    return at(int(std::floor(m.x * float(w))), int(std::floor(m.y * float(h))));
  float x = m.x * float(w) - 0.5f, y = m.y * float(h) - 0.5f;
  int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  float fx = x - float(x0), fy = y - float(y0);
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

Environment Environment::fromDesc(const SsEnvironmentDesc& desc, std::shared_ptr<const TextureImage> image) {
  for (float v : desc.rotation)
    require(std::isfinite(v) && std::abs(v) <= 1e3f, "environment rotation values must be finite and within 1e3");
  require(std::isfinite(desc.strength) && desc.strength >= 0.0f && desc.strength <= 1e6f,
          "environment strength must be in [0, 1e6], got " + std::to_string(desc.strength));
  Environment e;
  e.image = std::move(image);
  bool zero = true;
  for (float v : desc.rotation) zero = zero && v == 0.0f;
  if (!zero) e.rotation = glm::mat3(desc.rotation[0], desc.rotation[1], desc.rotation[2], desc.rotation[3],
                                    desc.rotation[4], desc.rotation[5], desc.rotation[6], desc.rotation[7],
                                    desc.rotation[8]);
  e.strength = desc.strength;
  return e;
}

glm::vec2 Environment::uv(const glm::vec3& direction) const {
  glm::vec3 d = rotation * direction;
  return {0.5f - std::atan2(d.y, d.x) / (2.0f * float(M_PI)),
          std::atan2(d.z, std::hypot(d.x, d.y)) / float(M_PI) + 0.5f};
}

glm::vec3 Environment::radiance(const glm::vec3& direction) const {
  if (!image) return glm::vec3(0.0f);
  glm::vec2 at = uv(direction);
  const int w = image->width(), h = image->height();
  float x = at.x * float(w) - 0.5f, y = at.y * float(h) - 0.5f;
  int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  float fx = x - float(x0), fy = y - float(y0);
  auto texel = [&](int i, int j) {
    return image->texel(((i % w) + w) % w, std::min(std::max(j, 0), h - 1));
  };
  return strength * glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), fx),
                             glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), fx), fy);
}

glm::vec3 perturbedNormal(const glm::vec3& rgb, float strength, const glm::vec3& normal, const glm::vec3& tangent,
                          const glm::vec3& bitangent) {
  if (glm::dot(tangent, tangent) == 0.0f) return normal;
  // Gram-Schmidt against the shading normal; the bitangent keeps the UVs' handedness.
  glm::vec3 t = tangent - normal * glm::dot(normal, tangent);
  if (glm::dot(t, t) < 1e-20f) return normal;
  t = glm::normalize(t);
  glm::vec3 b = glm::cross(normal, t);
  if (glm::dot(b, bitangent) < 0.0f) b = -b;
  glm::vec3 c = rgb * 2.0f - 1.0f;
  glm::vec3 n = c.x * t + c.y * b + c.z * normal;
  if (glm::dot(n, n) < 1e-20f) return normal;
  n = glm::normalize(n);
  if (strength != 1.0f) {
    n = normal + (n - normal) * std::max(strength, 0.0f);
    if (glm::dot(n, n) < 1e-20f) return normal;
    n = glm::normalize(n);
  }
  return n;
}

void triangleTangents(const glm::vec3 p[3], const glm::vec2 uv[3], glm::vec3& tangent, glm::vec3& bitangent) {
  glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  glm::vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
  float det = d1.x * d2.y - d2.x * d1.y;
  if (!(std::abs(det) > 1e-20f)) {
    tangent = bitangent = glm::vec3(0.0f);
    return;
  }
  tangent = (e1 * d2.y - e2 * d1.y) / det;
  bitangent = (e2 * d1.x - e1 * d2.x) / det;
}

}  // namespace subsplat
