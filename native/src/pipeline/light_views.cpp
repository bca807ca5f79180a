#include "pipeline/light_views.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace subsplat {

namespace {

glm::vec3 anyPerpendicular(const glm::vec3& d) {
  return std::abs(d.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
}

float farthestCorner(const glm::vec3& from, const Bounds& b) {
  float far = 0.0f;
  for (int i = 0; i < 8; ++i) {
    glm::vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    far = std::max(far, glm::length(c - from));
  }
  return far;
}

// up: the view's up vector (its image's rotation about forward: the faces of a cube must tile).
LightView perspectiveView(const SsLightDesc& light, const glm::vec3& forward, float tanHalfFov,
                          const Bounds& all, int resolution, const glm::vec3& up) {
  glm::vec3 position = glm::make_vec3(light.position);
  float far = std::max(farthestCorner(position, all) * 1.01f, 1e-6f);
  glm::mat4 view = glm::lookAt(position, position + forward, up);
  glm::mat4 proj = glm::perspective(2.0f * std::atan(tanHalfFov), 1.0f, far * 1e-5f, far);
  LightView v;
  v.light = &light;
  v.viewProj = proj * view;
  v.tanHalfFov = tanHalfFov;
  v.nearDepth = std::max(glm::length(all.center() - position) - all.radius(), far * 1e-3f);
  v.shadowTexelSize = 2.0f * tanHalfFov / float(resolution);
  return v;
}

}  // namespace

namespace {

// The views of lightViews, before their soft size.
std::vector<LightView> pointLikeViews(const SsLightDesc& light, const Bounds& translucent,
                                      const Bounds& all, int resolution) {
  std::vector<LightView> views;
  if (all.empty()) return views;
  if (light.type == SS_LIGHT_SUN) {
    // Lateral extent: the translucent objects' bounding sphere, where the
    // irradiance samples must be dense. Depth: every object, so opaque
    // objects between the sun and the translucent ones cast shadows.
    const Bounds& fit = translucent.empty() ? all : translucent;
    glm::vec3 dir = glm::normalize(glm::make_vec3(light.direction));
    glm::vec3 center = fit.center();
    float radius = std::max(fit.radius(), 1e-6f);
    float distance = glm::length(all.center() - center) + all.radius() + radius + 1e-3f;
    glm::vec3 eye = center - dir * distance;
    glm::mat4 view = glm::lookAt(eye, center, anyPerpendicular(dir));
    float far = 2.0f * distance + 1e-3f;
    glm::mat4 proj = glm::ortho(-radius, radius, -radius, radius, 0.0f, far);
    LightView v;
    v.light = &light;
    v.viewProj = proj * view;
    float texel = 2.0f * radius / float(resolution);
    v.orthoTexelArea = texel * texel;
    v.shadowTexelSize = texel;
    v.unshadowedOutside = true;
    v.nearDepth = glm::dot(center, dir) - all.radius() - glm::length(all.center() - center);
    views.push_back(v);
    return views;
  }
  constexpr float kSingleViewMaxCone = 150.0f * float(M_PI) / 180.0f;
  if (light.type == SS_LIGHT_SPOT && light.spot_size <= kSingleViewMaxCone) {
    glm::vec3 dir = glm::normalize(glm::make_vec3(light.direction));
    // A little wider than the cone, so the cone's edge is inside the view.
    float tanHalf = std::tan(std::min(0.5f * light.spot_size * 1.02f + 0.01f, 1.48f));
    views.push_back(perspectiveView(light, dir, tanHalf, all, resolution, anyPerpendicular(dir)));
    return views;
  }
  if (light.type == SS_LIGHT_AREA) {
    // A one-sided emitter: the five faces of a cube in its own frame that see in front of it, the
    // first facing where it faces, so that what it lights head-on is one view (a soft shadow's
    // filter does not reach across a seam between views: docs/SOFT_SHADOWS.md).
    glm::vec3 n = glm::normalize(glm::make_vec3(light.direction)), a = glm::normalize(glm::make_vec3(light.area_axis));
    a = glm::normalize(a - n * glm::dot(n, a));
    glm::vec3 b = glm::cross(n, a);
    views.push_back(perspectiveView(light, n, 1.0f, all, resolution, a));
    for (const glm::vec3& side : {a, -a, b, -b}) views.push_back(perspectiveView(light, side, 1.0f, all, resolution, n));
    return views;
  }
  const glm::vec3 faces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const glm::vec3& face : faces)
    views.push_back(perspectiveView(light, face, 1.0f, all, resolution, anyPerpendicular(face)));
  return views;
}

}  // namespace

std::vector<LightView> lightViews(const SsLightDesc& light, const Bounds& translucent,
                                  const Bounds& all, int resolution) {
  std::vector<LightView> views = pointLikeViews(light, translucent, all, resolution);
  for (LightView& v : views) {
    v.softSize = lightSoftSize(light);
    if (light.type == SS_LIGHT_AREA) areaSemiAxes(light, v.softAxes[0], v.softAxes[1], v.softRectangle);
  }
  return views;
}

void areaSemiAxes(const SsLightDesc& light, glm::vec3& a, glm::vec3& b, bool& rectangle) {
  glm::vec3 n = glm::normalize(glm::make_vec3(light.direction)), x = glm::make_vec3(light.area_axis);
  x = glm::normalize(x - n * glm::dot(n, x));
  bool twoSizes = light.area_shape == SS_AREA_RECTANGLE || light.area_shape == SS_AREA_ELLIPSE;
  a = x * (0.5f * light.area_size[0]);
  b = glm::cross(n, x) * (0.5f * (twoSizes ? light.area_size[1] : light.area_size[0]));
  rectangle = light.area_shape == SS_AREA_SQUARE || light.area_shape == SS_AREA_RECTANGLE;
}

float lightSoftSize(const SsLightDesc& light) {
  if (light.type == SS_LIGHT_SUN) return std::tan(0.5f * light.soft_size);
  if (light.type != SS_LIGHT_AREA) return light.soft_size;
  bool twoSizes = light.area_shape == SS_AREA_RECTANGLE || light.area_shape == SS_AREA_ELLIPSE;
  float w = light.area_size[0], h = twoSizes ? light.area_size[1] : light.area_size[0];
  bool round = light.area_shape == SS_AREA_DISK || light.area_shape == SS_AREA_ELLIPSE;
  return std::sqrt((round ? 0.25f * float(M_PI) * w * h : w * h) / float(M_PI));  // the disk of its area
}

}  // namespace subsplat
