#include "testing/scenes.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#ifdef SUBSPLAT_HAS_OPENIMAGEIO
#include <OpenImageIO/imageio.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>

namespace subsplat::testing {

SsMeshDesc Quad::desc(float halfSize, uint32_t material) const {
  SsMeshDesc d{};
  d.positions = positions.data();
  d.normals = normals.data();
  d.uvs = uvs.data();
  d.vertex_count = 4;
  d.indices = indices.data();
  d.triangle_count = 2;
  d.default_material = material;
  glm::mat4 m = glm::scale(glm::mat4(1.0f), glm::vec3(halfSize, halfSize, 1.0f));
  std::memcpy(d.object_to_world, glm::value_ptr(m), sizeof d.object_to_world);
  return d;
}

Box::Box(const glm::vec3& lo, const glm::vec3& hi)
    : positions{lo.x, lo.y, hi.z, hi.x, lo.y, hi.z, hi.x, hi.y, hi.z, lo.x, hi.y, hi.z,
                lo.x, lo.y, lo.z, hi.x, lo.y, lo.z, hi.x, hi.y, lo.z, lo.x, hi.y, lo.z},
      indices{0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1, 1, 5, 6, 1, 6, 2,
              2, 6, 7, 2, 7, 3, 3, 7, 4, 3, 4, 0} {}

SsMeshDesc Box::desc(uint32_t material) const {
  SsMeshDesc d{};
  d.positions = positions.data();
  d.vertex_count = 8;
  d.indices = indices.data();
  d.triangle_count = 12;
  d.default_material = material;
  for (int i = 0; i < 4; ++i) d.object_to_world[i * 5] = 1.0f;
  return d;
}

SsMaterialDesc greyMaterial(float albedo) {
  SsMaterialDesc m{};
  m.kind = SS_MATERIAL_OPAQUE;
  m.base_color[0] = m.base_color[1] = m.base_color[2] = albedo;
  m.roughness = 1.0f;
  m.eta = 1.5f;
  return m;
}

Sphere::Sphere(int segments, int rings) {
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      float theta = float(M_PI) * float(r) / float(rings), phi = 2.0f * float(M_PI) * float(s) / float(segments);
      glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      positions.insert(positions.end(), {n.x, n.y, n.z});
      normals.insert(normals.end(), {n.x, n.y, n.z});
      uvs.insert(uvs.end(), {float(s) / float(segments), 1.0f - float(r) / float(rings)});
    }
  auto vertex = [segments](int r, int s) { return uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      if (r > 0) indices.insert(indices.end(), {vertex(r, s), vertex(r + 1, s), vertex(r, s + 1)});
      if (r < rings - 1) indices.insert(indices.end(), {vertex(r, s + 1), vertex(r + 1, s), vertex(r + 1, s + 1)});
    }
}

SsMeshDesc Sphere::desc(const glm::vec3& centre, float radius, uint32_t material) const {
  SsMeshDesc d{};
  d.positions = positions.data();
  d.normals = normals.data();
  d.uvs = uvs.data();
  d.vertex_count = uint32_t(positions.size() / 3);
  d.indices = indices.data();
  d.triangle_count = uint32_t(indices.size() / 3);
  d.default_material = material;
  glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), centre), glm::vec3(radius));
  std::memcpy(d.object_to_world, glm::value_ptr(m), sizeof d.object_to_world);
  return d;
}

SsStatus setSlab(SsContext context, const Quad& quad, const SsMaterialDesc& material) {
  SsMeshDesc slab = quad.desc(2.0f, 0);
  SsCameraDesc camera = topDownCamera(0.5f);
  SsStatus status = ssSetMaterial(context, 0, &material);
  if (status == SS_OK) status = ssSetMesh(context, 0, &slab);
  if (status == SS_OK) status = ssSetCamera(context, &camera);
  return status;
}

SsStatus setLitSphere(SsContext context, const Sphere& sphere, const SsMaterialDesc& material) {
  SsMeshDesc desc = sphere.desc(glm::vec3(0.0f), 0.3f, 0);
  SsCameraDesc camera = topDownCamera(0.35f);
  SsLightDesc lights[2] = {sunLight(3.0f, 70.0f), {}};
  lights[1].type = SS_LIGHT_POINT;
  lights[1].color[0] = lights[1].color[1] = lights[1].color[2] = 1.0f;
  lights[1].strength = 20.0f;
  lights[1].position[0] = -0.3f, lights[1].position[2] = -0.6f;
  SsStatus status = ssSetMaterial(context, 0, &material);
  if (status == SS_OK) status = ssSetMesh(context, 0, &desc);
  if (status == SS_OK) status = ssSetCamera(context, &camera);
  if (status == SS_OK) status = ssSetLights(context, lights, 2);
  return status;
}

SsMaterialDesc skinMaterial(float mmPerUnit) {
  SsMaterialDesc m = marbleMaterial(mmPerUnit);
  const float sa[3] = {0.032f, 0.17f, 0.48f}, ss[3] = {0.74f, 0.88f, 1.01f};
  std::memcpy(m.sigma_a, sa, sizeof sa);
  std::memcpy(m.sigma_s_prime, ss, sizeof ss);
  return m;
}

SsMaterialDesc marbleMaterial(float mmPerUnit) {
  SsMaterialDesc m{};
  m.kind = SS_MATERIAL_DIPOLE;
  const float sa[3] = {0.0021f, 0.0041f, 0.0071f}, ss[3] = {2.19f, 2.62f, 3.00f};
  std::memcpy(m.sigma_a, sa, sizeof sa);
  std::memcpy(m.sigma_s_prime, ss, sizeof ss);
  m.eta = 1.3f;
  m.mm_per_unit = mmPerUnit;
  m.roughness = 0.5f;
  m.specular = 0.0f;
  return m;
}

SsCameraDesc topDownCamera(float halfWidth) {
  SsCameraDesc c{};
  glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  glm::mat4 proj = glm::ortho(-halfWidth, halfWidth, -halfWidth, halfWidth, 0.1f, 20.0f);
  std::memcpy(c.world_to_view, glm::value_ptr(view), sizeof c.world_to_view);
  std::memcpy(c.view_to_clip, glm::value_ptr(proj), sizeof c.view_to_clip);
  c.orthographic = 1;
  return c;
}

SsLightDesc sunLight(float strength, float incidenceDegrees) {
  SsLightDesc l{};
  l.type = SS_LIGHT_SUN;
  l.color[0] = l.color[1] = l.color[2] = 1.0f;
  l.strength = strength;
  float t = incidenceDegrees * float(M_PI) / 180.0f;
  l.direction[0] = std::sin(t);
  l.direction[2] = -std::cos(t);
  return l;
}

std::string changedLines(const std::string& before, const std::string& after) {
  std::istringstream a(before), b(after);
  std::string x, y, out;
  while (std::getline(a, x) && std::getline(b, y))
    if (x != y) out += x + " -> " + y.substr(y.find('=') + 1) + "\n";
  return out;
}

}  // namespace subsplat::testing

namespace subsplat::testing {

std::string writeComparison(const std::string& name, const std::vector<float>& ours,
                            const std::vector<float>& reference, int width, int height) {
  const char* env = std::getenv("SUBSPLAT_TEST_OUTPUT");
  std::filesystem::path folder = env ? env : "test_output";
  std::filesystem::create_directories(folder);
  double mean = 0.0;
  size_t pixels = size_t(width) * height;
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) mean += reference[4 * i + size_t(c)] / double(3 * pixels);
  auto write = [&](const std::string& suffix, const std::function<glm::vec3(size_t)>& colour) {
    std::vector<uint8_t> bytes(pixels * 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        glm::vec3 c = glm::clamp(colour(size_t(height - 1 - y) * width + x), 0.0f, 1.0f);
        for (int k = 0; k < 3; ++k) bytes[(size_t(y) * width + x) * 3 + size_t(k)] = uint8_t(std::lround(255.0f * c[k]));
      }
    std::string path = (folder / (name + "_" + suffix + ".png")).string();
#ifdef SUBSPLAT_HAS_OPENIMAGEIO  // the tests' pictures; a replay-only build has no tests
    auto out = OIIO::ImageOutput::create(path);
    if (out && out->open(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8))) {
      out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
      out->close();
    }
#endif
    return path;
  };
  auto display = [](float v) { return std::pow(std::max(v, 0.0f), 1.0f / 2.2f); };
  write("ours", [&](size_t i) { return glm::vec3(display(ours[4 * i]), display(ours[4 * i + 1]), display(ours[4 * i + 2])); });
  write("reference", [&](size_t i) {
    return glm::vec3(display(reference[4 * i]), display(reference[4 * i + 1]), display(reference[4 * i + 2]));
  });
  return write("difference", [&](size_t i) {
    double d = 0.0;
    for (int c = 0; c < 3; ++c) d += std::abs(ours[4 * i + size_t(c)] - reference[4 * i + size_t(c)]) / 3.0;
    float t = float(std::clamp(d / std::max(mean, 1e-12) * 10.0, 0.0, 1.0));
    return glm::vec3(t, 1.0f - std::abs(2.0f * t - 1.0f), 1.0f - t);
  });
}

}  // namespace subsplat::testing
