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
  gl::Buffer positions, normals, indices, triangleMaterialBuffer;
  gl::Texture triangleMaterials;  // buffer texture of dense material indices
  std::vector<uint32_t> materialIds; // caller's material id per triangle
  // CPU copies for REFERENCE (object space; normals after repair).
  std::vector<glm::vec3> cpuPositions, cpuNormals;
  std::vector<glm::vec2> cpuUvs;  // empty when the caller gave none
  std::vector<uint32_t> cpuIndices;
  std::vector<uint32_t> denseMaterials;  // per triangle, after resolveMaterials()
  uint32_t triangleCount = 0;
  glm::mat4 objectToWorld{1.0f};
  Bounds worldBounds;
  bool translucent = false;  // resolved at render time
};

struct Material {
  SsMaterialDesc desc{};
  std::shared_ptr<const SplatKernel> kernel;  // translucent only
};

// The GPU layout of one material (common.glsl: Material).
struct MaterialGpu {
  float baseColorKind[4];
  float optics[4];
  float ranges[4];
};

class Scene {
 public:
  void setMaterial(uint32_t id, const SsMaterialDesc& desc);
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
  const std::vector<Material>& denseMaterials() const { return dense_; }
  const std::vector<SsLightDesc>& lights() const { return lights_; }
  const SsCameraDesc& camera() const { return camera_; }
  bool hasCamera() const { return hasCamera_; }
  Bounds bounds(bool translucentOnly) const;
  uint64_t materialVersion() const { return materialVersion_; }

 private:
  std::map<uint32_t, Material> materials_;
  std::map<uint32_t, Mesh> meshes_;
  std::vector<Material> dense_;
  std::map<uint32_t, int> denseIndex_;
  std::vector<SsLightDesc> lights_;
  SsCameraDesc camera_{};
  bool hasCamera_ = false;
  uint64_t materialVersion_ = 0, resolvedVersion_ = ~0ull;
  int nextMeshIndex_ = 0;
};

DipoleMaterial dipoleMaterial(const SsMaterialDesc& desc);
void validateMaterial(const SsMaterialDesc& desc);

}  // namespace subsplat
