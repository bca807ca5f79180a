// What a frame is rendered from: meshes on the GPU, materials, lights, camera.
// Everything is validated here, on the way in.
#pragma once

#include <glm/glm.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/gl.h"
#include "material/profile_set.h"
#include "material/splat_kernel.h"
#include "subsplat/subsplat.h"

namespace subsplat {

struct Bounds {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  bool empty() const { return lo.x > hi.x; }
  void extend(const glm::vec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  void extend(const Bounds& b) { if (!b.empty()) { extend(b.lo); extend(b.hi); } }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  float radius() const { return 0.5f * glm::length(hi - lo); }
};

struct Mesh {
  int index = 0;  // dense index written to the buffers
  gl::VertexArray vertexArray;
  gl::Buffer positions, normals, uvs, indices, triangleMaterialBuffer;
  gl::Texture triangleMaterials;  // buffer texture of dense material indices
  std::vector<uint32_t> materialIds; // caller's material id per triangle
  // CPU copies for REFERENCE (object space; normals after repair).
  std::vector<glm::vec3> cpuPositions, cpuNormals;
  std::vector<glm::vec2> cpuUvs;  // empty when the caller gave none
  bool hasUvs() const { return !cpuUvs.empty(); }
  std::vector<uint32_t> cpuIndices;
  std::vector<uint32_t> denseMaterials;  // per triangle, after resolveMaterials()
  uint32_t triangleCount = 0;
  glm::mat4 objectToWorld{1.0f};
  Bounds worldBounds;
  bool translucent = false;  // resolved at render time
};

// A material as the caller set it.
struct Material {
  SsMaterialDesc desc{};  // desc.profiles is not kept; see profiles
  std::shared_ptr<const ProfileSet> profiles;               // SUBEDIT
  std::vector<std::shared_ptr<const SplatKernel>> kernels;  // DIPOLE: 1; SUBEDIT: one per palette entry
};

// What the renderers index: one entry per opaque or DIPOLE material and one
// per palette entry of a SUBEDIT material, the material's entries in a row
// (the first is its base). Buffers store entry indices.
struct MaterialEntry {
  SsMaterialDesc desc{};
  std::shared_ptr<const SplatKernel> kernel;    // translucent only
  std::shared_ptr<const ProfileSet> profiles;   // SUBEDIT: the material's set
  int base = 0;                                 // the material's first entry
  uint32_t id = 0;                              // the caller's material id
  // The entry of a surface point of this material with texture coordinate uv
  // (entries of a SUBEDIT material follow its palette).
  int entryAt(const glm::vec2* uv) const {
    return mapped() && uv ? base + profiles->profileAt(uv->x, uv->y) : base;
  }
  // More than one profile: a map to look up (a one-texel map is homogeneous).
  bool mapped() const { return profiles && profiles->profileCount() > 1; }
};

// The GPU layout of one entry (common.glsl: Material).
struct MaterialGpu {
  float baseColorKind[4];
  float optics[4];
  float ranges[4];
  uint32_t profileMap[4];
};

class Scene {
 public:
  // profiles: the SUBEDIT material's set (desc.profiles is the API's handle to it).
  void setMaterial(uint32_t id, const SsMaterialDesc& desc, std::shared_ptr<const ProfileSet> profiles = nullptr);
  void setMesh(uint32_t objectId, const SsMeshDesc& desc);
  void removeMesh(uint32_t objectId);
  void clear();
  void setLights(const SsLightDesc* lights, uint32_t count);
  void setCamera(const SsCameraDesc& camera);

  // Dense material table and kernel layers; throws if a mesh uses a
  // material that was never set. Uploads per-triangle dense indices.
  void resolveMaterials();

  const std::map<uint32_t, Mesh>& meshes() const { return meshes_; }
  const std::map<uint32_t, Material>& materials() const { return materials_; }
  const std::vector<MaterialEntry>& denseMaterials() const { return dense_; }
  // Palette indices of every SUBEDIT map, one after another (R16UI buffer
  // texture; MaterialGpu::profileMap holds each map's offset and size).
  GLuint profileMaps() const { return profileMapTexture_.id(); }
  // Whether some object can carry more than one translucent entry, so that
  // R_d(x_i, x_o) = sqrt(P_i P_o) needs both ends (eq. 8).
  bool heterogeneous() const { return heterogeneous_; }
  const std::vector<SsLightDesc>& lights() const { return lights_; }
  const SsCameraDesc& camera() const { return camera_; }
  bool hasCamera() const { return hasCamera_; }
  Bounds bounds(bool translucentOnly) const;
  uint64_t materialVersion() const { return materialVersion_; }

 private:
  std::map<uint32_t, Material> materials_;
  std::map<uint32_t, Mesh> meshes_;
  std::vector<MaterialEntry> dense_;
  gl::Buffer profileMapBuffer_;
  gl::Texture profileMapTexture_;
  bool heterogeneous_ = false;
  std::map<uint32_t, int> denseIndex_;
  std::vector<SsLightDesc> lights_;
  SsCameraDesc camera_{};
  bool hasCamera_ = false;
  uint64_t materialVersion_ = 0, resolvedVersion_ = ~0ull;
  int nextMeshIndex_ = 0;
};

DipoleMaterial dipoleMaterial(const SsMaterialDesc& desc);
bool isTranslucent(const SsMaterialDesc& desc);
void validateMaterial(const SsMaterialDesc& desc);

}  // namespace subsplat
