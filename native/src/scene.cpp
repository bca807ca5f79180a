#include "scene.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>

#include "util/error.h"
#include "world_light.h"

namespace subsplat {

namespace {

bool finite(const float* v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

std::string vec3String(const float* v) {
  return "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + ")";
}

}  // namespace

bool isTranslucent(const SsMaterialDesc& m) { return m.kind == SS_MATERIAL_DIPOLE || m.kind == SS_MATERIAL_SUBEDIT; }

void validateMaterial(const SsMaterialDesc& m) {
  require(m.kind == SS_MATERIAL_OPAQUE || m.kind == SS_MATERIAL_DIPOLE || m.kind == SS_MATERIAL_SUBEDIT ||
              m.kind == SS_MATERIAL_HOLDOUT,
          "material kind " + std::to_string(m.kind) + " is not OPAQUE, DIPOLE, SUBEDIT or HOLDOUT");
  require(finite(m.base_color, 3) && m.base_color[0] >= 0 && m.base_color[1] >= 0 &&
              m.base_color[2] >= 0,
          "base colour must be finite and non-negative, got " + vec3String(m.base_color));
  require(std::isfinite(m.roughness) && m.roughness >= 0 && m.roughness <= 1,
          "roughness must be in [0, 1], got " + std::to_string(m.roughness));
  require(std::isfinite(m.specular) && m.specular >= 0 && m.specular <= 1,
          "specular must be in [0, 1], got " + std::to_string(m.specular));
  validateTexture(m.color_texture, "colour texture");
  validateTexture(m.normal_texture, "normal texture");
  require(std::isfinite(m.normal_strength) && m.normal_strength >= 0 && m.normal_strength <= 10,
          "normal strength must be in [0, 10], got " + std::to_string(m.normal_strength));
  if (m.kind == SS_MATERIAL_OPAQUE || m.kind == SS_MATERIAL_HOLDOUT) return;
  require(m.profile_model == SS_PROFILE_DIPOLE || m.profile_model == SS_PROFILE_TABULATED,
          "profile model " + std::to_string(m.profile_model) + " is not DIPOLE (0) or TABULATED (1)");
  require(std::isfinite(m.eta) && m.eta >= 1.0f && m.eta <= 3.0f,
          "eta must be in [1, 3], got " + std::to_string(m.eta));
  require(std::isfinite(m.mm_per_unit) && m.mm_per_unit >= 1e-6f && m.mm_per_unit <= 1e9f,
          "mm_per_unit must be in [1e-6, 1e9], got " + std::to_string(m.mm_per_unit));
  if (m.kind == SS_MATERIAL_SUBEDIT) return;  // the profile set is checked where it is resolved
  require(finite(m.sigma_a, 3), "sigma_a must be finite, got " + vec3String(m.sigma_a));
  require(finite(m.sigma_s_prime, 3),
          "sigma_s' must be finite, got " + vec3String(m.sigma_s_prime));
  for (int c = 0; c < 3; ++c) {
    require(m.sigma_a[c] > 0 && m.sigma_a[c] <= 1e4,
            "sigma_a must be in (0, 1e4] per mm, got " + vec3String(m.sigma_a));
    require(m.sigma_s_prime[c] >= 0 && m.sigma_s_prime[c] <= 1e4,
            "sigma_s' must be in [0, 1e4] per mm, got " + vec3String(m.sigma_s_prime));
  }
}

DipoleMaterial dipoleMaterial(const SsMaterialDesc& d) {
  DipoleMaterial m;
  for (int c = 0; c < 3; ++c) m.channels[c] = {d.sigma_a[c], d.sigma_s_prime[c], d.eta};
  m.mmPerUnit = d.mm_per_unit;
  m.model = d.profile_model;
  return m;
}

void Scene::setMaterial(uint32_t id, const SsMaterialDesc& desc, std::shared_ptr<const ProfileSet> profiles,
                        std::shared_ptr<const TextureImage> color, std::shared_ptr<const TextureImage> normal) {
  validateMaterial(desc);
  require(desc.kind != SS_MATERIAL_SUBEDIT || profiles, "a SUBEDIT material needs a profile set");
  require(!desc.color_texture.image || color, "the colour texture's image is missing");
  require(!desc.normal_texture.image || normal, "the normal texture's image is missing");
  Material m;
  m.desc = desc;
  m.desc.profiles = nullptr;
  m.desc.color_texture.image = m.desc.normal_texture.image = nullptr;
  if (m.desc.normal_strength == 0.0f) m.desc.normal_strength = 1.0f;
  if (desc.kind != SS_MATERIAL_HOLDOUT) {
    if (color) m.color = Texture::fromDesc(desc.color_texture, std::move(color));
    if (normal) m.normal = Texture::fromDesc(desc.normal_texture, std::move(normal));
  }
  auto it = materials_.find(id);
  const Material* old = it != materials_.end() ? &it->second : nullptr;
  if (desc.kind == SS_MATERIAL_DIPOLE) {
    // Rebuild the kernel table only when the dipole itself changed.
    bool same = old && old->desc.kind == SS_MATERIAL_DIPOLE &&
                std::memcmp(old->desc.sigma_a, desc.sigma_a, sizeof desc.sigma_a) == 0 &&
                std::memcmp(old->desc.sigma_s_prime, desc.sigma_s_prime, sizeof desc.sigma_s_prime) == 0 &&
                old->desc.eta == desc.eta && old->desc.mm_per_unit == desc.mm_per_unit &&
                old->desc.profile_model == desc.profile_model;
    if (same) {
      m.kernels = old->kernels;
      m.transport = old->transport;
    } else {
      DipoleMaterial medium = dipoleMaterial(desc);
      m.kernels.push_back(SplatKernel::forDipole(medium));
      if (desc.profile_model == SS_PROFILE_TABULATED) m.transport = std::make_shared<const TransportTables>(medium.channels);
    }
  } else if (desc.kind == SS_MATERIAL_SUBEDIT) {
    m.profiles = std::move(profiles);
    bool same = old && old->profiles == m.profiles && old->desc.mm_per_unit == desc.mm_per_unit;
    m.kernels = same ? old->kernels : m.profiles->kernels(desc.mm_per_unit);
  }
  materials_[id] = std::move(m);
  ++materialVersion_;
}

void Scene::setMesh(uint32_t objectId, const SsMeshDesc& d) {
  require(d.positions != nullptr, "mesh " + std::to_string(objectId) + ": positions is NULL");
  require(d.indices != nullptr, "mesh " + std::to_string(objectId) + ": indices is NULL");
  require(d.vertex_count > 0 && d.triangle_count > 0,
          "mesh " + std::to_string(objectId) + " is empty (" + std::to_string(d.vertex_count) +
              " vertices, " + std::to_string(d.triangle_count) + " triangles)");
  require(d.vertex_count <= (1u << 28) && d.triangle_count <= (1u << 28),
          "mesh " + std::to_string(objectId) + " exceeds 2^28 vertices or triangles");
  require(finite(d.object_to_world, 16),
          "mesh " + std::to_string(objectId) + ": object_to_world is not finite");
  std::string name = "mesh " + std::to_string(objectId);
  for (uint32_t v = 0; v < d.vertex_count; ++v)
    if (!finite(d.positions + 3 * size_t(v), 3))
      fail(SS_INVALID_ARGUMENT, name + ": vertex " + std::to_string(v) +
                                    " has a non-finite position " + vec3String(d.positions + 3 * size_t(v)));
  for (size_t i = 0; i < 3 * size_t(d.triangle_count); ++i)
    if (d.indices[i] >= d.vertex_count)
      fail(SS_INVALID_ARGUMENT, name + ": index " + std::to_string(d.indices[i]) + " at " +
                                    std::to_string(i) + " is out of range (" +
                                    std::to_string(d.vertex_count) + " vertices)");

  // Normals: the caller's where finite and non-zero, else area-weighted.
  std::vector<glm::vec3> normals(d.vertex_count, glm::vec3(0.0f));
  const glm::vec3* p = reinterpret_cast<const glm::vec3*>(d.positions);
  bool recompute = d.normals == nullptr;
  if (!recompute) {
    for (uint32_t v = 0; v < d.vertex_count && !recompute; ++v) {
      glm::vec3 n = glm::make_vec3(d.normals + 3 * size_t(v));
      recompute = !finite(d.normals + 3 * size_t(v), 3) || glm::dot(n, n) < 1e-12f;
      normals[v] = n;
    }
  }
  if (recompute) {
    std::fill(normals.begin(), normals.end(), glm::vec3(0.0f));
    for (uint32_t t = 0; t < d.triangle_count; ++t) {
      const uint32_t* i = d.indices + 3 * size_t(t);
      glm::vec3 n = glm::cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]]);
      for (int k = 0; k < 3; ++k) normals[i[k]] += n;
    }
    for (glm::vec3& n : normals) n = glm::dot(n, n) > 0 ? glm::normalize(n) : glm::vec3(0, 0, 1);
  }

  Mesh mesh;
  auto existing = meshes_.find(objectId);
  mesh.index = existing != meshes_.end() ? existing->second.index : nextMeshIndex_++;
  // The object's old mesh goes before the new one is allocated: less memory at the peak, and a
  // mesh beyond the memory budget leaves the object without one (the call failed).
  if (existing != meshes_.end()) {
    meshes_.erase(existing);
    if (observer_) observer_->meshRemoved(objectId);
    resolvedVersion_ = ~0ull;
  }
  mesh.objectToWorld = glm::make_mat4(d.object_to_world);
  mesh.triangleCount = d.triangle_count;
  mesh.materialIds.assign(d.triangle_count, d.default_material);
  if (d.triangle_materials)
    mesh.materialIds.assign(d.triangle_materials, d.triangle_materials + d.triangle_count);
  mesh.cpuPositions.assign(p, p + d.vertex_count);
  mesh.cpuNormals = normals;
  if (d.uvs != nullptr) {
    require(finite(d.uvs, 2 * size_t(d.vertex_count)), name + ": a texture coordinate is not finite");
    const glm::vec2* uv = reinterpret_cast<const glm::vec2*>(d.uvs);
    mesh.cpuUvs.assign(uv, uv + d.vertex_count);
  }
  mesh.cpuIndices.assign(d.indices, d.indices + 3 * size_t(d.triangle_count));
  for (uint32_t v = 0; v < d.vertex_count; ++v)
    mesh.worldBounds.extend(glm::vec3(mesh.objectToWorld * glm::vec4(p[v], 1.0f)));
  require(glm::all(glm::lessThan(glm::abs(mesh.worldBounds.lo), glm::vec3(1e15f))) &&
              glm::all(glm::lessThan(glm::abs(mesh.worldBounds.hi), glm::vec3(1e15f))),
          name + ": world-space bounds are not finite");

  if (observer_) observer_->meshSet(objectId, mesh);
  meshes_[objectId] = std::move(mesh);
  resolvedVersion_ = ~0ull;
  ++geometryVersion_;
}

void Scene::removeMesh(uint32_t objectId) {
  require(meshes_.erase(objectId) == 1, "no mesh with object id " + std::to_string(objectId));
  if (observer_) observer_->meshRemoved(objectId);
  ++geometryVersion_;
}

void Scene::clear() {
  if (observer_)
    for (const auto& [id, mesh] : meshes_) observer_->meshRemoved(id);
  meshes_.clear();
  materials_.clear();
  dense_.clear();
  denseIndex_.clear();
  lights_.clear();
  hasCamera_ = false;
  environment_ = Environment{};
  ++environmentVersion_;
  ++materialVersion_;
  ++geometryVersion_;
}

void Scene::setLights(const SsLightDesc* lights, uint32_t count) {
  require(count == 0 || lights != nullptr, "lights is NULL with a count of " + std::to_string(count));
  require(count <= 256, "at most 256 lights are supported, got " + std::to_string(count));
  std::vector<SsLightDesc> list(lights, lights + count);
  int worlds = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const SsLightDesc& l = list[i];
    std::string name = "light " + std::to_string(i);
    require(l.type == SS_LIGHT_POINT || l.type == SS_LIGHT_SPOT || l.type == SS_LIGHT_SUN ||
                l.type == SS_LIGHT_WORLD || l.type == SS_LIGHT_AREA,
            name + ": unknown type " + std::to_string(l.type));
    if (l.type == SS_LIGHT_WORLD) {
      require(finite(l.world_below, 3) && l.world_below[0] >= 0 && l.world_below[1] >= 0 && l.world_below[2] >= 0,
              name + ": the world's radiance below the horizon must be finite and non-negative");
      require(finite(l.world_sh, 27), name + ": the world's spherical harmonics must be finite");
      require(l.world_sh[0] >= 0 && l.world_sh[1] >= 0 && l.world_sh[2] >= 0,
              name + ": the world's spherical harmonics' first coefficient (its mean radiance) must be non-negative");
      for (float v : l.world_sh)
        require(std::abs(v) <= 1e6f, name + ": the world's spherical harmonics must be within 1e6, got " + std::to_string(v));
      require(++worlds == 1, name + ": a second world light (at most one)");
      require(l.world_directions >= -1 && l.world_directions <= kMaxWorldDirections,
              name + ": world directions must be -1 (unshadowed), 0 (automatic) or in [1, " +
                  std::to_string(kMaxWorldDirections) + "], got " + std::to_string(l.world_directions));
    }
    require(finite(l.color, 3) && finite(l.position, 3) && finite(l.direction, 3) &&
                std::isfinite(l.strength) && std::isfinite(l.spot_size) && std::isfinite(l.spot_blend),
            name + ": non-finite parameter");
    require(l.strength >= 0 && l.color[0] >= 0 && l.color[1] >= 0 && l.color[2] >= 0,
            name + ": negative strength or colour");
    require(std::isfinite(l.soft_size) && l.soft_size >= 0.0f &&
                (l.type != SS_LIGHT_SUN || l.soft_size <= float(M_PI / 2)) && l.soft_size <= 1e6f,
            name + ": soft size must be in [0, pi/2] radians for a sun and in [0, 1e6] for other lights, got " +
                std::to_string(l.soft_size));
    if (l.type == SS_LIGHT_AREA) {
      glm::vec3 axis = glm::make_vec3(l.area_axis), normal = glm::make_vec3(l.direction);
      require(finite(l.area_axis, 3) && std::isfinite(l.area_size[0]) && std::isfinite(l.area_size[1]),
              name + ": non-finite area parameter");
      require(l.area_shape >= SS_AREA_SQUARE && l.area_shape <= SS_AREA_ELLIPSE,
              name + ": unknown area shape " + std::to_string(l.area_shape));
      bool twoSizes = l.area_shape == SS_AREA_RECTANGLE || l.area_shape == SS_AREA_ELLIPSE;
      require(l.area_size[0] > 0.0f && l.area_size[0] <= 1e6f && (!twoSizes || (l.area_size[1] > 0.0f && l.area_size[1] <= 1e6f)),
              name + ": area sizes must be in (0, 1e6]");
      require(glm::length(axis) > 1e-12f && glm::length(normal) > 1e-12f &&
                  std::abs(glm::dot(glm::normalize(axis), glm::normalize(normal))) < 1e-3f,
              name + ": the area light's axis must be non-zero and perpendicular to its direction");
    }
    if (l.type == SS_LIGHT_SPOT || l.type == SS_LIGHT_SUN || l.type == SS_LIGHT_AREA)
      require(glm::length(glm::make_vec3(l.direction)) > 1e-12f, name + ": zero direction");
    if (l.type == SS_LIGHT_SPOT)
      require(l.spot_size > 0 && l.spot_size <= float(M_PI) && l.spot_blend >= 0 && l.spot_blend <= 1,
              name + ": spot size must be in (0, pi] and blend in [0, 1]");
  }
  lights_ = std::move(list);
  ++geometryVersion_;
}

void Scene::setEnvironment(const SsEnvironmentDesc& desc, std::shared_ptr<const TextureImage> image) {
  environment_ = Environment::fromDesc(desc, std::move(image));
  ++environmentVersion_;
}

void Scene::setCamera(const SsCameraDesc& camera) {
  require(finite(camera.world_to_view, 16) && finite(camera.view_to_clip, 16),
          "camera matrices must be finite");
  glm::mat4 v = glm::make_mat4(camera.world_to_view), p = glm::make_mat4(camera.view_to_clip);
  require(std::abs(glm::determinant(v)) > 1e-20f && std::abs(glm::determinant(p)) > 1e-30f,
          "camera matrices must be invertible");
  camera_ = camera;
  hasCamera_ = true;
}

void Scene::resolveMaterials() {
  if (resolvedVersion_ == materialVersion_) return;
  dense_.clear();
  denseIndex_.clear();
  std::vector<uint16_t> maps;
  for (const auto& [id, material] : materials_) {
    int base = int(dense_.size());
    denseIndex_[id] = base;
    size_t entries = std::max<size_t>(material.kernels.size(), 1);
    for (size_t e = 0; e < entries; ++e) {
      MaterialEntry entry;
      entry.desc = material.desc;
      entry.kernel = e < material.kernels.size() ? material.kernels[e] : nullptr;
      entry.base = base;
      entry.id = id;
      entry.profiles = material.profiles;
      entry.transport = material.transport;
      entry.color = material.color;
      entry.normal = material.normal;
      dense_.push_back(std::move(entry));
    }
    if (dense_[size_t(base)].mapped()) {
      const std::vector<uint16_t>& map = material.profiles->map();
      maps.insert(maps.end(), map.begin(), map.end());
    }
  }
  if (maps.empty()) maps.push_back(0);
  profileMaps_ = std::move(maps);
  heterogeneous_ = tabulated_ = textured_ = false;
  for (const MaterialEntry& e : dense_)
    heterogeneous_ |= e.mapped(), tabulated_ |= bool(e.transport), textured_ |= bool(e.color) || bool(e.normal);
  for (auto& [objectId, mesh] : meshes_) {
    std::vector<uint32_t> dense(mesh.materialIds.size());
    mesh.translucent = false;
    for (size_t t = 0; t < dense.size(); ++t) {
      auto it = denseIndex_.find(mesh.materialIds[t]);
      if (it == denseIndex_.end())
        fail(SS_INVALID_ARGUMENT, "mesh " + std::to_string(objectId) + " uses material " +
                                      std::to_string(mesh.materialIds[t]) + ", which was never set");
      dense[t] = uint32_t(it->second);
      mesh.translucent |= isTranslucent(dense_[size_t(it->second)].desc);
    }
    // Two translucent materials on one object scatter into each other.
    int translucentMaterial = -1;
    for (uint32_t m : dense) {
      if (!isTranslucent(dense_[m].desc)) continue;
      heterogeneous_ |= translucentMaterial >= 0 && translucentMaterial != int(m);
      translucentMaterial = int(m);
    }
    mesh.denseMaterials = std::move(dense);
  }
  resolvedVersion_ = materialVersion_;
  ++resolutionCount_;
}

Bounds Scene::bounds(bool translucentOnly) const {
  Bounds b;
  for (const auto& [id, mesh] : meshes_)
    if (!translucentOnly || mesh.translucent) b.extend(mesh.worldBounds);
  return b;
}

}  // namespace subsplat
