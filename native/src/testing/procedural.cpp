#include "testing/procedural.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>

namespace subsplat::testing {

namespace {

// Uniform numbers from mt19937_64, whose output the standard fixes (the standard's
// distributions are not, and would give other scenes with another library).
class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  double logUniform(double lo, double hi) { return lo * std::pow(hi / lo, uniform()); }
  int pick(int count) { return std::min(int(uniform() * count), count - 1); }
  glm::dvec3 direction() {  // uniform on the sphere
    double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI), r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  std::mt19937_64 engine_;
};

const PresetMedium* const kPresets = kPresetMedia;
constexpr int kPresetCount = kPresetMediaCount;

// A closed surface over (u, v) in [0, 1)^2 on a grid: a sphere's topology (v from pole to pole,
// one vertex per pole) or a torus's (both wrap). Normals from the triangles, area-weighted;
// triangles wound outwards (by the sign of the enclosed volume).
ProceduralMesh closedSurface(int rings, int segments, bool torus, const std::function<glm::dvec3(double, double)>& at) {
  ProceduralMesh mesh;
  std::vector<glm::dvec3> points;
  auto vertex = [&](int r, int s) -> uint32_t {  // r in [0, rings], s wraps
    s = ((s % segments) + segments) % segments;
    if (torus) return uint32_t((r % rings) * segments + s);
    if (r == 0) return 0;
    if (r == rings) return uint32_t(1 + (rings - 1) * segments);
    return uint32_t(1 + (r - 1) * segments + s);
  };
  if (torus) {
    for (int r = 0; r < rings; ++r)
      for (int s = 0; s < segments; ++s) points.push_back(at(double(s) / segments, double(r) / rings));
  } else {
    points.push_back(at(0.0, 0.0));
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segments; ++s) points.push_back(at(double(s) / segments, double(r) / rings));
    points.push_back(at(0.0, 1.0));
  }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      uint32_t a = vertex(r, s), b = vertex(r, s + 1), c = vertex(r + 1, s), d = vertex(r + 1, s + 1);
      if (torus || r > 0) mesh.indices.insert(mesh.indices.end(), {a, c, b});
      if (torus || r < rings - 1) mesh.indices.insert(mesh.indices.end(), {b, c, d});
    }
  double volume = 0.0;
  for (size_t i = 0; i < mesh.indices.size(); i += 3)
    volume += glm::dot(points[mesh.indices[i]], glm::cross(points[mesh.indices[i + 1]], points[mesh.indices[i + 2]]));
  if (volume < 0.0)
    for (size_t i = 0; i < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  std::vector<glm::dvec3> normals(points.size(), glm::dvec3(0.0));
  for (size_t i = 0; i < mesh.indices.size(); i += 3) {
    const glm::dvec3 &p0 = points[mesh.indices[i]], &p1 = points[mesh.indices[i + 1]], &p2 = points[mesh.indices[i + 2]];
    glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);  // twice the area, outwards
    for (int k = 0; k < 3; ++k) normals[mesh.indices[i + k]] += n;
  }
  for (size_t i = 0; i < points.size(); ++i) {
    glm::dvec3 n = glm::length(normals[i]) > 0.0 ? glm::normalize(normals[i]) : glm::dvec3(0, 0, 1);
    mesh.positions.insert(mesh.positions.end(), {float(points[i].x), float(points[i].y), float(points[i].z)});
    mesh.normals.insert(mesh.normals.end(), {float(n.x), float(n.y), float(n.z)});
  }
  return mesh;
}

glm::dvec3 sphereDirection(double u, double v) {
  double theta = M_PI * v, phi = 2.0 * M_PI * u;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)};
}

void store(float out[16], const glm::mat4& m) { std::memcpy(out, glm::value_ptr(m), 16 * sizeof(float)); }
void store3(float out[3], const glm::dvec3& v) { out[0] = float(v.x), out[1] = float(v.y), out[2] = float(v.z); }

}  // namespace

uint64_t sceneSeed(SceneSet set, int index) {
  // splitmix64 of the index, the set in the top bit
  uint64_t z = uint64_t(index) + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (z & ~(1ull << 63)) | (uint64_t(set) << 63);
}

const char* setName(SceneSet set) { return set == SceneSet::Calibration ? "calibration" : "test"; }

SsMeshDesc ProceduralMesh::desc() const {
  SsMeshDesc d{};
  d.positions = positions.data();
  d.normals = normals.data();
  d.vertex_count = uint32_t(positions.size() / 3);
  d.indices = indices.data();
  d.triangle_count = uint32_t(indices.size() / 3);
  d.default_material = material;
  store(d.object_to_world, glm::mat4(1.0f));
  return d;
}

SsStatus ProceduralScene::apply(SsContext context) const {
  SsStatus status = ssClearScene(context);
  for (size_t i = 0; i < materials.size() && status == SS_OK; ++i)
    status = ssSetMaterial(context, uint32_t(i), &materials[i]);
  for (size_t i = 0; i < meshes.size() && status == SS_OK; ++i) {
    SsMeshDesc desc = meshes[i].desc();
    status = ssSetMesh(context, uint32_t(i), &desc);
  }
  if (status == SS_OK) status = ssSetLights(context, lights.data(), uint32_t(lights.size()));
  if (status == SS_OK) status = ssSetCamera(context, &camera);
  return status;
}

ProceduralScene proceduralScene(SceneSet set, int index, int width, int height) {
  ProceduralScene scene;
  scene.seed = sceneSeed(set, index);
  Random random(scene.seed);
  char text[256];

  // The shape, about unit size, then turned, scaled and placed.
  static const char* kShapes[] = {"blob", "plate", "rod", "torus"};
  int shape = random.pick(4);
  ProceduralMesh object;
  if (shape == 1 || shape == 2) {  // a thin plate (a leaf, an ear) or a rod (a finger, a candle)
    double thin = shape == 1 ? random.logUniform(0.02, 0.1) : random.logUniform(0.1, 0.3);
    glm::dvec3 axes = shape == 1 ? glm::dvec3(1.0, random.uniform(0.4, 1.0), thin) : glm::dvec3(1.0, thin, thin * random.uniform(0.7, 1.0));
    double bend = random.uniform(-0.3, 0.3);  // a curl along x
    object = closedSurface(24, 48, false, [&](double u, double v) {
      glm::dvec3 p = sphereDirection(u, v) * axes;
      p.z += bend * (p.x * p.x - 0.5);
      return p;
    });
  } else if (shape == 3) {
    double minor = random.logUniform(0.08, 0.35);
    object = closedSurface(24, 64, true, [&](double u, double v) {
      double phi = 2.0 * M_PI * u, theta = 2.0 * M_PI * v;
      double ring = 1.0 + minor * std::cos(theta);
      return glm::dvec3(ring * std::cos(phi), ring * std::sin(phi), minor * std::sin(theta));
    });
  } else {  // a blob: a sphere with three random ripples, squashed
    glm::dvec3 axes(1.0, random.uniform(0.6, 1.0), random.uniform(0.5, 1.0));
    struct Ripple { glm::dvec3 axis; double frequency, phase, amplitude; } ripples[3];
    for (Ripple& r : ripples)
      r = {random.direction(), random.uniform(1.0, 4.0), random.uniform(0.0, 2.0 * M_PI), random.uniform(0.03, 0.15)};
    object = closedSurface(32, 64, false, [&](double u, double v) {
      glm::dvec3 d = sphereDirection(u, v);
      double radius = 1.0;
      for (const Ripple& r : ripples) radius += r.amplitude * std::sin(r.frequency * glm::dot(d, r.axis) * M_PI + r.phase);
      return d * radius * axes;
    });
  }
  double units = random.logUniform(0.1, 10.0);  // bounding radius in scene units
  glm::dvec3 axis = random.direction();
  glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), random.uniform(0.0, 2.0 * M_PI), axis);
  double reach = 0.0;
  for (size_t i = 0; i < object.positions.size(); i += 3)
    reach = std::max(reach, glm::length(glm::dvec3(object.positions[i], object.positions[i + 1], object.positions[i + 2])));
  double scale = units / reach;
  double lowest = 0.0;
  for (size_t i = 0; i < object.positions.size(); i += 3) {
    glm::dvec3 p = glm::dvec3(turn * glm::dvec4(object.positions[i], object.positions[i + 1], object.positions[i + 2], 1.0)) * scale;
    glm::dvec3 n = glm::dvec3(turn * glm::dvec4(object.normals[i], object.normals[i + 1], object.normals[i + 2], 0.0));
    store3(&object.positions[i], p);
    store3(&object.normals[i], glm::normalize(n));
    lowest = std::min(lowest, p.z);
  }
  scene.radius = float(units);

  // The medium: a measured preset, or random (then a third of the time index-matched).
  double sizeMm = random.logUniform(1.0, 10000.0);  // the bounding radius, 1 mm to 10 m
  scene.mmPerUnit = float(sizeMm / units);
  SsMaterialDesc medium{};
  medium.kind = SS_MATERIAL_DIPOLE;
  medium.mm_per_unit = scene.mmPerUnit;
  medium.roughness = float(random.uniform(0.2, 0.8));
  medium.specular = float(random.uniform(0.0, 0.5));
  medium.profile_model = random.uniform() < 0.3 ? SS_PROFILE_TABULATED : SS_PROFILE_DIPOLE;
  int preset = random.pick(kPresetCount + 3);  // three in fourteen: random media
  std::string mediumName;
  if (preset < kPresetCount) {
    std::memcpy(medium.sigma_s_prime, kPresets[preset].sigmaSPrime, sizeof medium.sigma_s_prime);
    std::memcpy(medium.sigma_a, kPresets[preset].sigmaA, sizeof medium.sigma_a);
    medium.eta = 1.3f;
    mediumName = kPresets[preset].name;
  } else {
    for (int c = 0; c < 3; ++c) {
      medium.sigma_s_prime[c] = float(random.logUniform(0.05, 10.0));
      medium.sigma_a[c] = float(random.logUniform(0.0005, 1.0));
    }
    medium.eta = random.uniform() < 0.33 ? 1.0f : float(random.uniform(1.1, 1.6));
    std::snprintf(text, sizeof text, "random eta %.2f", medium.eta);
    mediumName = text;
  }
  scene.materials.push_back(medium);
  object.material = 0;
  scene.meshes.push_back(std::move(object));

  // An opaque floor under it, two times in five.
  bool floor = random.uniform() < 0.4;
  if (floor) {
    SsMaterialDesc grey{};
    grey.kind = SS_MATERIAL_OPAQUE;
    grey.base_color[0] = grey.base_color[1] = grey.base_color[2] = float(random.uniform(0.2, 0.8));
    grey.roughness = 1.0f;
    scene.materials.push_back(grey);
    ProceduralMesh plane;
    double half = 6.0 * units, z = lowest - 0.02 * units;
    plane.positions = {float(-half), float(-half), float(z), float(half), float(-half), float(z),
                       float(half), float(half), float(z), float(-half), float(half), float(z)};
    plane.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    plane.indices = {0, 1, 2, 0, 2, 3};
    plane.material = 1;
    scene.meshes.push_back(std::move(plane));
  }

  // One or two lights from above the floor's plane, around the object: some light it from
  // behind as the camera sees it.
  int lightCount = random.uniform() < 0.35 ? 2 : 1;
  std::string lightNames;
  static const char* kLightNames[] = {"sun", "spot", "point"};
  for (int l = 0; l < lightCount; ++l) {
    int type = random.pick(3);
    double elevation = random.uniform(10.0, 80.0) * M_PI / 180.0, azimuth = random.uniform(0.0, 2.0 * M_PI);
    glm::dvec3 toLight(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    SsLightDesc light{};
    glm::dvec3 tint(random.uniform(0.8, 1.0), random.uniform(0.8, 1.0), random.uniform(0.8, 1.0));
    store3(light.color, tint);
    if (type == 0) {
      light.type = SS_LIGHT_SUN;
      light.strength = 3.0f;
      store3(light.direction, -toLight);
    } else {
      double distance = units * random.uniform(2.0, 6.0);
      light.type = type == 1 ? SS_LIGHT_SPOT : SS_LIGHT_POINT;
      light.strength = float(3.0 * 4.0 * M_PI * distance * distance);  // about 3 W/m^2 at the object
      store3(light.position, toLight * distance);
      store3(light.direction, -toLight);
      if (type == 1) {
        double cover = 2.0 * std::asin(std::min(1.0 / (distance / units), 1.0));
        light.spot_size = float(std::min(cover * random.uniform(1.2, 2.5), 170.0 * M_PI / 180.0));
        light.spot_blend = float(random.uniform(0.0, 0.3));
      }
    }
    scene.lights.push_back(light);
    lightNames += (l ? "+" : "") + std::string(kLightNames[type]);
  }

  // The camera: any azimuth, from a little below the object's centre to high above, the
  // object filling most of a 40-degree view.
  double elevation = random.uniform(-10.0, 70.0) * M_PI / 180.0, azimuth = random.uniform(0.0, 2.0 * M_PI);
  glm::dvec3 toCamera(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  double fov = 40.0 * M_PI / 180.0, distance = units / std::sin(fov / 2.0) * random.uniform(1.0, 1.5);
  glm::mat4 view = glm::lookAt(glm::vec3(toCamera * distance), glm::vec3(0.0f), glm::vec3(0, 0, 1));
  glm::mat4 proj = glm::perspective(float(fov), float(width) / float(height), float(std::max(distance - 8.0 * units, 0.01 * units)),
                                    float(distance + 12.0 * units));
  {  // as the library measures it (auto_quality.cpp, nearestPixel): at the near side of the
     // translucent object's bounding box's sphere
    glm::dvec3 lo(1e30), hi(-1e30);
    const std::vector<float>& p = scene.meshes[0].positions;
    for (size_t i = 0; i < p.size(); i += 3) {
      lo = glm::min(lo, glm::dvec3(p[i], p[i + 1], p[i + 2]));
      hi = glm::max(hi, glm::dvec3(p[i], p[i + 1], p[i + 2]));
    }
    double depth = glm::length(toCamera * distance - 0.5 * (lo + hi)) - 0.5 * glm::length(hi - lo);
    scene.pixel = float(2.0 * std::max(depth, 1e-6) * std::tan(fov / 2.0) / height);
  }
  store(scene.camera.world_to_view, view);
  store(scene.camera.view_to_clip, proj);

  std::snprintf(text, sizeof text, "%s r=%.3g m (%.3g units) %s %s; %s%s", kShapes[shape], sizeMm / 1000.0, units, mediumName.c_str(),
                medium.profile_model == SS_PROFILE_TABULATED ? "tabulated" : "dipole", lightNames.c_str(), floor ? "; floor" : "");
  scene.description = text;
  return scene;
}

int referenceResolution(int resolution, double texelsPerRange) {
  for (int rung : kRungs)
    if (rung >= 4 * resolution && texelsPerRange * rung / resolution >= kReferenceTexels) return rung;
  return 2048;
}

SsStatus renderAt(SsContext context, int method, int width, int height, int resolution, float targetError,
                  std::vector<float>& rgba, SsStats& stats) {
  SsSettings settings = ssDefaultSettings();
  settings.method = method;
  settings.irradiance_resolution = resolution;
  settings.target_error = targetError;
  settings.levels = 0;
  settings.shadow_resolution = 2048;
  rgba.assign(size_t(width) * size_t(height) * 4, 0.0f);
  SsStatus status = ssSetSettings(context, &settings);
  if (status == SS_OK) status = ssRender(context, width, height, rgba.data());
  if (status == SS_OK) status = ssGetStats(context, &stats);
  return status;
}

double relativeRmse(const std::vector<float>& image, const std::vector<float>& reference) {
  double difference = 0.0, total = 0.0;
  for (size_t i = 0; i + 3 < reference.size() && i + 3 < image.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      double d = double(image[i + c]) - double(reference[i + c]);
      difference += d * d;
      total += double(reference[i + c]) * double(reference[i + c]);
    }
  return total > 0.0 ? std::sqrt(difference / total) : (difference > 0.0 ? INFINITY : 0.0);
}

}  // namespace subsplat::testing
