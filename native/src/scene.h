// What a frame is rendered from: meshes, materials, lights, camera, as plain
// CPU data (no GL: REFERENCE and the scene files use it without a context).
// Everything is validated here, on the way in. The GPU's copy of the meshes
// and material indices is pipeline/gpu_scene.h, told of every mesh change.
#pragma once

#include <glm/glm.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "material/profile_set.h"
#include "material/splat_kernel.h"
#include "material/texture.h"
#include "material/transport_model.h"
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
  std::vector<uint32_t> materialIds; // caller's material id per triangle
  // Object space; normals after repair.
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
  SsMaterialDesc desc{};  // desc's handles (profiles, textures' images) are not kept; see below
  std::shared_ptr<const ProfileSet> profiles;               // SUBEDIT
  Texture color, normal;                                    // docs/TEXTURES.md
  std::vector<std::shared_ptr<const SplatKernel>> kernels;  // DIPOLE: 1; SUBEDIT: one per palette entry
  std::shared_ptr<const TransportTables> transport;          // DIPOLE with the TABULATED model
};

// What the renderers index: one entry per opaque or DIPOLE material and one
// per palette entry of a SUBEDIT material, the material's entries in a row
// (the first is its base). Buffers store entry indices.
struct MaterialEntry {
  SsMaterialDesc desc{};
  std::shared_ptr<const SplatKernel> kernel;    // translucent only
  std::shared_ptr<const ProfileSet> profiles;   // SUBEDIT: the material's set
  std::shared_ptr<const TransportTables> transport;  // the TABULATED model's angular and thin-part tables
  Texture color, normal;                        // the material's (every entry of it)
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

// Told of every mesh change, so that a copy (the GPU's, pipeline/gpu_scene.h)
// follows the scene.
class MeshObserver {
 public:
  virtual ~MeshObserver() = default;
  // A mesh was set; when this throws, the object is left without a mesh.
  virtual void meshSet(uint32_t objectId, const Mesh& mesh) = 0;
  virtual void meshRemoved(uint32_t objectId) = 0;
};

class Scene {
 public:
  // profiles: the SUBEDIT material's set (desc.profiles is the API's handle to it); color, normal:
  // the images of desc's textures (needed where desc names one).
  void setMaterial(uint32_t id, const SsMaterialDesc& desc, std::shared_ptr<const ProfileSet> profiles = nullptr,
                   std::shared_ptr<const TextureImage> color = nullptr,
                   std::shared_ptr<const TextureImage> normal = nullptr);
  void setMesh(uint32_t objectId, const SsMeshDesc& desc);
  void removeMesh(uint32_t objectId);
  void clear();
  void setLights(const SsLightDesc* lights, uint32_t count);
  void setCamera(const SsCameraDesc& camera);
  // image: desc.image's (null: no environment).
  void setEnvironment(const SsEnvironmentDesc& desc, std::shared_ptr<const TextureImage> image);
  const Environment& environment() const { return environment_; }
  // Counts the environment's changes (a GPU copy is current while it has the same count).
  uint64_t environmentVersion() const { return environmentVersion_; }

  // At most one; nullptr: none.
  void setMeshObserver(MeshObserver* observer) { observer_ = observer; }

  // Dense material table and per-triangle dense indices; throws if a mesh
  // uses a material that was never set.
  void resolveMaterials();
  // Counts the resolutions that changed something: a copy of the dense
  // indices and profile maps is current while it has the same count.
  uint64_t resolutionCount() const { return resolutionCount_; }

  const std::map<uint32_t, Mesh>& meshes() const { return meshes_; }
  const std::map<uint32_t, Material>& materials() const { return materials_; }
  const std::vector<MaterialEntry>& denseMaterials() const { return dense_; }
  // Palette indices of every SUBEDIT map, one after another (at least one;
  // MaterialGpu::profileMap holds each map's offset and size).
  const std::vector<uint16_t>& profileMaps() const { return profileMaps_; }
  // Whether some object can carry more than one translucent entry, so that
  // R_d(x_i, x_o) = sqrt(P_i P_o) needs both ends (eq. 8).
  bool heterogeneous() const { return heterogeneous_; }
  // Whether some material has the TABULATED model (its passes: thickness, transmission).
  bool tabulated() const { return tabulated_; }
  const std::vector<SsLightDesc>& lights() const { return lights_; }
  const SsCameraDesc& camera() const { return camera_; }
  bool hasCamera() const { return hasCamera_; }
  Bounds bounds(bool translucentOnly) const;
  uint64_t materialVersion() const { return materialVersion_; }
  // Counts the changes of meshes and lights (a transport precomputed for them serves while it
  // has the same count: MATERIAL_EDIT).
  uint64_t geometryVersion() const { return geometryVersion_; }
  // Whether some material reads a texture (the camera buffers then keep each pixel's albedo).
  bool textured() const { return textured_; }

 private:
  std::map<uint32_t, Material> materials_;
  std::map<uint32_t, Mesh> meshes_;
  std::vector<MaterialEntry> dense_;
  std::vector<uint16_t> profileMaps_;
  bool heterogeneous_ = false, tabulated_ = false, textured_ = false;
  std::map<uint32_t, int> denseIndex_;
  std::vector<SsLightDesc> lights_;
  SsCameraDesc camera_{};
  bool hasCamera_ = false;
  Environment environment_;
  uint64_t environmentVersion_ = 0;
  uint64_t materialVersion_ = 0, resolvedVersion_ = ~0ull, resolutionCount_ = 0, geometryVersion_ = 0;
  int nextMeshIndex_ = 0;
  MeshObserver* observer_ = nullptr;
};

DipoleMaterial dipoleMaterial(const SsMaterialDesc& desc);
bool isTranslucent(const SsMaterialDesc& desc);
void validateMaterial(const SsMaterialDesc& desc);

}  // namespace subsplat
