#include "reference/reference_renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include "material/dipole.h"
#include "material/profile_set.h"
#include "material/transport_model.h"
#include "pipeline/light_views.h"
#include "reference/lighting.h"
#include "reference/ray_scene.h"
#include "reference/squared_radius_table.h"
#include "util/camera.h"
#include "util/error.h"
#include "util/pixel_filter.h"
#include "world_light.h"

namespace subsplat {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// One material entry's profile in scene units (R_d in 1 / unit^2): a dipole
// or a SubEdit palette entry; and its surface terms.
struct Profile {
  bool translucent = false;
  float scale[3]{}, zr[3]{}, zv[3]{}, sigmaTr[3]{};  // the dipole's, in float (docs/REFERENCE.md)
  std::vector<SegmentedProfile> segmented;  // SUBEDIT: per channel, in mm
  std::vector<std::shared_ptr<const TabulatedProfile>> tabulated;  // TABULATED: per channel, in mm
  SquaredRadiusTable table;  // TABULATED: the three channels' P in 1 / unit^2 against r^2 in unit^2
  const TransportTables* transport = nullptr;                    // TABULATED
  bool holdout = false;
  double mmPerUnit = 1.0;
  double support = 0.0, minZr = 0.0;  // minZr: the length the profile bends over
  float eta = 1.0f, roughness = 0.5f, specular = 0.0f;
  glm::vec3 baseColor{0.0f};
  glm::vec3 world{0.0f};  // world_light.h: unshadowedResponse

  Profile(const MaterialEntry& e, int index)
      : translucent(isTranslucent(e.desc)), holdout(e.desc.kind == SS_MATERIAL_HOLDOUT), mmPerUnit(e.desc.mm_per_unit), eta(e.desc.eta),
        roughness(e.desc.roughness), specular(e.desc.specular), baseColor(glm::make_vec3(e.desc.base_color)),
        world(unshadowedResponse(e)) {
    const SsMaterialDesc& d = e.desc;
    if (d.kind == SS_MATERIAL_SUBEDIT) {
      const ProfileSet& set = *e.profiles;
      for (int c = 0; c < 3; ++c) {
        segmented.push_back(set.channel(index - e.base, c));
        support = std::max(support, segmented.back().radiusForEnergy(ReferenceRenderer::kSupportEnergy) / mmPerUnit);
      }
      minZr = set.radiusMm() / set.segments() / mmPerUnit;
      return;
    }
    if (!translucent) return;
    minZr = std::numeric_limits<double>::infinity();
    if (e.transport) {  // the TABULATED model (material/transport_model.h)
      transport = e.transport.get();
      for (int c = 0; c < 3; ++c) {
        DipoleChannel channel{d.sigma_a[c], d.sigma_s_prime[c], d.eta};
        tabulated.push_back(std::make_shared<TabulatedProfile>(channel));
        support = std::max(support, tabulated.back()->radiusForEnergy(ReferenceRenderer::kSupportEnergy) / mmPerUnit);
        // The once-scattered peak bends within a fraction of a mean free path: near x_o cells are
        // cut to kFinestCell of a twentieth of one (a plane then converges within 0.3 % of the
        // closed form, tests/blender/test_plane.py).
        minZr = std::min(minZr, 0.05 / mediumExtinction(channel) / mmPerUnit);
      }
      table = tabulate(tabulated, mmPerUnit);
      return;
    }
    for (int c = 0; c < 3; ++c) {
      Dipole dipole({d.sigma_a[c], d.sigma_s_prime[c], d.eta});
      double unit = d.mm_per_unit;  // mm per scene unit
      scale[c] = float(dipole.reducedAlbedo() / (4.0 * M_PI));
      zr[c] = float(dipole.realSourceDepth() / unit);
      zv[c] = float(dipole.virtualSourceHeight() / unit);
      sigmaTr[c] = float(dipole.effectiveExtinction() * unit);
      support = std::max(support, dipole.radiusForEnergy(ReferenceRenderer::kSupportEnergy) / unit);
      minZr = std::min(minZr, dipole.realSourceDepth() / unit);
    }
  }

  // R_d(r) per channel, 1 / unit^2 (Jensen et al. 2001; material/dipole.h), for a cell of `area`
  // (unit^2) at squared distance r2. The TABULATED profile has the once-scattered light's 1 / r
  // peak at r = 0, which a value at the centroid of a cell as large as its distance misses (the
  // cells near x_o, which refinement stops cutting at the finest cell): a cell of radius
  // h = sqrt(area / pi) takes P's mean over the disk of radius h around x_o when nearer than h, over
  // the ring from r - h to r + h when nearer than 8 h (energy-true at the peak), else P at r.
  void evaluate(double r2, double out[3], double area = 0.0) const {
    if (!tabulated.empty() && area > 0.0 && 64.0 * area > M_PI * r2) {
      double h = std::sqrt(area / M_PI) * mmPerUnit, r = std::sqrt(r2) * mmPerUnit, perUnit2 = mmPerUnit * mmPerUnit;
      double lo = std::max(r - h, 0.0), hi = r + h;
      if (r < h) lo = 0.0, hi = h;
      for (int c = 0; c < 3; ++c) {
        const RadialProfile& p = *tabulated[size_t(c)];
        out[c] = (p.energyWithin(hi) - p.energyWithin(lo)) / (M_PI * (hi * hi - lo * lo)) * perUnit2;
      }
      return;
    }
    if (!segmented.empty()) {
      double r = std::sqrt(r2) * mmPerUnit, perUnit2 = mmPerUnit * mmPerUnit;
      for (int c = 0; c < 3; ++c) out[c] = segmented[size_t(c)].value(r) * perUnit2;
      return;
    }
    if (!tabulated.empty()) return table.values(r2, out);
    for (int c = 0; c < 3; ++c) out[c] = dipoleReflectance(float(r2), zr[c], zv[c], sigmaTr[c], scale[c]);
  }
  // Each channel at its own squared distance (the TABULATED model's forward shift).
  void evaluate(const double r2[3], double out[3], double area = 0.0) const {
    if (r2[1] == r2[0] && r2[2] == r2[0]) return evaluate(r2[0], out, area);
    if (!tabulated.empty() && !(area > 0.0 && 64.0 * area > M_PI * std::min({r2[0], r2[1], r2[2]}))) {
      for (int c = 0; c < 3; ++c) out[c] = table.value(r2[c], c);  // each channel at its own radius
      return;
    }
    evaluate(r2[0], out, area);
    double other[3];
    for (int c = 1; c < 3; ++c) {
      evaluate(r2[c], other, area);
      out[c] = other[c];
    }
  }
};

// R_d(x_i, x_o) = sqrt(P_i(r) P_o(r)) (eq. 8); one profile when they agree.
struct ProfilePair {
  const Profile* in;
  const Profile* out;
  double finestCell;

  // Whether evaluate reads the cell's area (a TABULATED profile's peak), so others skip computing it.
  bool readsArea() const { return !in->tabulated.empty() || !out->tabulated.empty(); }
  void evaluate(const double r2[3], double k[3], double area = 0.0) const {
    in->evaluate(r2, k, area);
    if (in == out) return;
    double o[3];
    out->evaluate(r2, o, area);
    for (int c = 0; c < 3; ++c) k[c] = std::sqrt(k[c] * o[c]);
  }
};

struct SurfaceSample {
  glm::vec3 position;   // the cell's centroid
  glm::vec3 corners[3];
  glm::vec2 uvs[3];     // the corners' texture coordinates: refined parts look up their own profile
  glm::vec3 flux;       // E dA, W (TABULATED: times the incidence factor)
  glm::vec3 fluxMu0;    // TABULATED: the flux of each light times its incidence cosine, summed
  glm::vec3 normal;     // TABULATED: the shading normal, facing the (first) light
  glm::vec3 shift[3];   // TABULATED: per channel, the forward shift (Entering::shift)
  float shiftReach;     // the longest of the three
  float diameter;       // longest edge of the cell
  float area;           // the cell's area (the TABULATED profile's peak reads it)
  uint32_t material;    // the entry at the centroid
  uint32_t base;        // the material's first entry
  bool mapped;          // several profiles and UVs: the UVs choose among them
};

// Where a cell is refined, each part's profile: the entry at its centroid's UV
// when the material is mapped, so profile boundaries are as sharp as the
// refinement (eq. 8 evaluated per part), not as the cell.
struct CellProfiles {
  const std::vector<MaterialEntry>* entries;
  const std::vector<Profile>* profiles;
  uint32_t base;
  bool mapped;
  const Profile& at(const glm::dvec2& uv) const {
    glm::vec2 at(uv);
    return (*profiles)[size_t((*entries)[base].entryAt(&at))];
  }
};

// The samples of one object, sorted into a uniform grid.
struct ObjectSamples {
  std::vector<SurfaceSample> samples;
  std::vector<uint32_t> cellStart;  // cells + 1 offsets into samples
  glm::vec3 origin{0.0f};
  float cellSize = 1.0f;
  glm::ivec3 dims{1};
  double support = 0.0;
  // The support plus the longest cell edge: a sample reaches x_o within the support while its
  // centre is nearer than the support plus its own edge (a cell's points lie within its longest
  // edge of its centroid). Where the profile is shorter than a cell (a metre-sized object of a
  // millimetre medium), the support alone missed the cells around x_o (stop 50).
  double reach = 0.0;
  double longestShift = 0.0;  // the longest forward shift (SurfaceSample::shift)

  void buildGrid() {
    Bounds b;
    double longest = 0.0;
    for (const SurfaceSample& s : samples) {
      b.extend(s.position), longest = std::max(longest, double(s.diameter));
      longestShift = std::max(longestShift, double(s.shiftReach));
    }
    reach = support + longest + longestShift;
    origin = b.lo;
    glm::vec3 extent = glm::max(b.hi - b.lo, glm::vec3(1e-6f));
    cellSize = float(std::max(reach * 0.5, 1e-9));
    // At most about 4M cells: bigger cells only cost time, never accuracy.
    while (double(extent.x / cellSize + 1) * (extent.y / cellSize + 1) * (extent.z / cellSize + 1) > 4.0e6)
      cellSize *= 1.5f;
    dims = glm::ivec3(extent / cellSize) + 1;
    size_t cells = size_t(dims.x) * dims.y * dims.z;
    std::vector<uint32_t> cellOf(samples.size());
    cellStart.assign(cells + 1, 0);
    for (size_t i = 0; i < samples.size(); ++i) {
      cellOf[i] = uint32_t(cellIndex(cellCoord(samples[i].position)));
      ++cellStart[cellOf[i] + 1];
    }
    for (size_t c = 0; c < cells; ++c) cellStart[c + 1] += cellStart[c];
    std::vector<SurfaceSample> sorted(samples.size());
    std::vector<uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
    for (size_t i = 0; i < samples.size(); ++i) sorted[fill[cellOf[i]]++] = samples[i];  // stable
    samples = std::move(sorted);
  }
  glm::ivec3 cellCoord(const glm::vec3& p) const {
    return glm::clamp(glm::ivec3(glm::floor((p - origin) / cellSize)), glm::ivec3(0), dims - 1);
  }
  size_t cellIndex(const glm::ivec3& c) const { return (size_t(c.z) * dims.y + c.y) * dims.x + c.x; }
};

// Flux of one cell, refined into four while it is large against its distance
// to x_o (its irradiance stays the sample's; each part has its own profile).
// sum: B(x_o) in rgb; alpha: the TABULATED model's exitance-weighted incidence cosine (fluxMu0).
// diameter2 and area: the cell's longest edge squared and its area; a part's are a quarter of
// its cell's (cut at the edges' midpoints, each part is the cell at half the size).
void addCell(const glm::dvec3& xo, const glm::dvec3 (&p)[3], const glm::dvec2 (&uv)[3], const glm::dvec3& flux,
             const glm::dvec3& fluxMu0, const glm::dvec3 (&shift)[3], double diameter2, double area, ProfilePair pair,
             const CellProfiles& cell, int depth, glm::dvec4& sum, uint64_t& evaluations) {
  glm::dvec3 centroid = (p[0] + p[1] + p[2]) / 3.0;
  glm::dvec3 offset = xo - centroid;
  // Each channel's distance from where its light is centred (the forward shift); the cell is cut
  // while it is large against the nearest of them, where the profile bends most.
  double r2s[3];
  for (int c = 0; c < 3; ++c) {
    glm::dvec3 o = offset - shift[c];
    r2s[c] = glm::dot(o, o);
  }
  const double r2 = std::min({r2s[0], r2s[1], r2s[2]});
  constexpr double kRatio2 = ReferenceRenderer::kRefineRatio * ReferenceRenderer::kRefineRatio;
  if (depth < ReferenceRenderer::kMaxDepth && diameter2 > kRatio2 * r2 && diameter2 > pair.finestCell * pair.finestCell) {
    const glm::dvec3 pm[3] = {0.5 * (p[0] + p[1]), 0.5 * (p[1] + p[2]), 0.5 * (p[2] + p[0])};
    const glm::dvec2 um[3] = {0.5 * (uv[0] + uv[1]), 0.5 * (uv[1] + uv[2]), 0.5 * (uv[2] + uv[0])};
    const glm::dvec3 quarter = 0.25 * flux, quarterMu0 = 0.25 * fluxMu0;
    const glm::dvec3 parts[4][3] = {{p[0], pm[0], pm[2]}, {pm[0], p[1], pm[1]}, {pm[2], pm[1], p[2]}, {pm[0], pm[1], pm[2]}};
    const glm::dvec2 partUvs[4][3] = {{uv[0], um[0], um[2]}, {um[0], uv[1], um[1]}, {um[2], um[1], uv[2]}, {um[0], um[1], um[2]}};
    for (int i = 0; i < 4; ++i)
      addCell(xo, parts[i], partUvs[i], quarter, quarterMu0, shift, 0.25 * diameter2, 0.25 * area, pair, cell, depth + 1,
              sum, evaluations);
    return;
  }
  if (cell.mapped && depth > 0) pair.in = &cell.at((uv[0] + uv[1] + uv[2]) / 3.0);
  double k[3];
  pair.evaluate(r2s, k, area);
  ++evaluations;
  glm::dvec3 kernel(k[0], k[1], k[2]);
  sum += glm::dvec4(kernel * flux, glm::dot(kernel, fluxMu0));
}

// B(x_o): every sample of the object within the support (eq. 5); alpha as addCell's. no: the
// normal at x_o (facing the camera), for the TABULATED model's side weight.
glm::dvec4 exitanceAt(const ObjectSamples& object, const glm::vec3& xo, const glm::vec3& no, const Profile& outProfile,
                      const std::vector<MaterialEntry>& entries, const std::vector<Profile>& profiles,
                      uint64_t& evaluations) {
  glm::dvec4 sum(0.0);
  const double support = object.support;
  glm::ivec3 lo = object.cellCoord(xo - glm::vec3(float(object.reach)));
  glm::ivec3 hi = object.cellCoord(xo + glm::vec3(float(object.reach)));
  glm::dvec3 x(xo);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        size_t cell = object.cellIndex({cx, y, z});
        for (uint32_t i = object.cellStart[cell]; i < object.cellStart[cell + 1]; ++i) {
          const SurfaceSample& s = object.samples[i];
          glm::dvec3 offset = x - glm::dvec3(s.position);
          double r2 = glm::dot(offset, offset);
          const double reach = support + double(s.diameter) + double(s.shiftReach);  // ObjectSamples::reach's, for this cell
          if (r2 >= reach * reach) continue;
          const Profile& in = profiles[s.material];
          ProfilePair pair{&in, &outProfile, ReferenceRenderer::kFinestCell * std::min(in.minZr, outProfile.minZr)};
          double side = in.transport ? sideWeight(double(glm::dot(s.normal, no))) : 1.0;
          if (side <= 0.0) continue;
          glm::dvec3 flux = side * glm::dvec3(s.flux), fluxMu0 = side * glm::dvec3(s.fluxMu0);
          const glm::dvec3 shift[3] = {s.shift[0], s.shift[1], s.shift[2]};
          double r2s[3];
          for (int c = 0; c < 3; ++c) {
            glm::dvec3 o = offset - shift[c];
            r2s[c] = glm::dot(o, o);
          }
          const double nearest2 = std::min({r2s[0], r2s[1], r2s[2]});  // addCell's
          double diameter = s.diameter;
          if (diameter > ReferenceRenderer::kRefineRatio * std::sqrt(nearest2) && diameter > pair.finestCell) {
            const glm::dvec3 corners[3] = {s.corners[0], s.corners[1], s.corners[2]};
            const glm::dvec2 uvs[3] = {s.uvs[0], s.uvs[1], s.uvs[2]};
            CellProfiles cell{&entries, &profiles, s.base, s.mapped};
            double diameter2 = std::max({glm::dot(corners[1] - corners[0], corners[1] - corners[0]),
                                         glm::dot(corners[2] - corners[1], corners[2] - corners[1]),
                                         glm::dot(corners[0] - corners[2], corners[0] - corners[2])});
            double area = pair.readsArea() ? 0.5 * glm::length(glm::cross(corners[1] - corners[0], corners[2] - corners[0])) : 0.0;
            addCell(x, corners, uvs, flux, fluxMu0, shift, diameter2, area, pair, cell, 0, sum, evaluations);
            continue;
          }
          double k[3];
          pair.evaluate(r2s, k, pair.readsArea() ? double(s.area) : 0.0);
          ++evaluations;
          glm::dvec3 kernel(k[0], k[1], k[2]);
          sum += glm::dvec4(kernel * flux, glm::dot(kernel, fluxMu0));
        }
      }
  return sum;
}

glm::vec3 interpolate(const std::vector<glm::vec3>& values, const glm::uvec3& t, const glm::vec3& w) {
  return w.x * values[t.x] + w.y * values[t.y] + w.z * values[t.z];
}

// A point just off the surface on the side the direction leaves towards.
glm::vec3 offsetOrigin(const glm::vec3& p, const glm::vec3& geometricNormal, const glm::vec3& direction,
                       float epsilon) {
  return p + geometricNormal * (glm::dot(geometricNormal, direction) >= 0.0f ? epsilon : -epsilon);
}

// The first hit along origin + t direction, t in (tNear, tFar), that `counts` accepts; the others
// are passed through.
template <typename Counts>
Hit firstHit(const RayScene& rays, const glm::vec3& origin, const glm::vec3& direction, float tNear, float tFar,
             const Counts& counts) {
  float t = tNear;
  for (int crossings = 0; crossings < 64; ++crossings) {
    Hit hit = rays.intersect(origin, direction, t, tFar);
    if (!hit.valid() || counts(hit)) return hit;
    t = hit.distance + rays.epsilon();
  }
  return Hit{};
}

// Whether p sees the light's sample. ignoredMesh >= 0: that mesh's surfaces never block (the light
// entering a translucent object, whose own shape shadows it from the light's centre only, as the
// irradiance buffer's depth test does: irradiance_buffer.frag, docs/SOFT_SHADOWS.md).
bool visible(const RayScene& rays, const glm::vec3& p, const glm::vec3& ng, const LightSample& light,
             int ignoredMesh = -1) {
  float eps = rays.epsilon();
  glm::vec3 origin = offsetOrigin(p, ng, light.towardsLight, eps);
  float far = std::isinf(light.distance) ? std::numeric_limits<float>::infinity()
                                         : std::max(light.distance - 2.0f * eps, 0.0f);
  if (ignoredMesh < 0) return !rays.occluded(origin, light.towardsLight, 0.0f, far);
  return !firstHit(rays, origin, light.towardsLight, 0.0f, far, [&](const Hit& h) { return h.mesh != ignoredMesh; })
              .valid();
}

// The share of a soft light (docs/SOFT_SHADOWS.md) that p sees: shadow rays to kSoftShadowRays points
// of its disk, seen from p (a sun: directions within its cone; a point, spot or area light: a disk
// of its radius facing p), on a Vogel spiral. softSize as LightView's (light_views.h).
constexpr int kSoftShadowRays = 16;
float softVisibility(const RayScene& rays, const glm::vec3& p, const glm::vec3& ng, const LightSample& light,
                     const SsLightDesc& desc, float softSize, int ignoredMesh = -1) {
  // The light's extent: an area light's own shape (its semi-axes, a rectangle or an ellipse), else a
  // disk of radius softSize across the ray (a sun's: tan of half its angle).
  glm::vec3 w = light.towardsLight, a, b;
  bool rectangle = false;
  if (desc.type == SS_LIGHT_AREA) {
    areaSemiAxes(desc, a, b, rectangle);
  } else {
    a = glm::normalize(glm::cross(w, std::abs(w.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0)));
    b = glm::cross(w, a) * softSize;
    a *= softSize;
  }
  const float golden = float(M_PI) * (3.0f - std::sqrt(5.0f));
  int seen = 0;
  for (int k = 0; k < kSoftShadowRays; ++k) {
    glm::vec2 d;
    if (rectangle) {  // stratified over the square
      int side = int(std::lround(std::sqrt(double(kSoftShadowRays))));
      d = glm::vec2((float(k % side) + 0.5f) / float(side), (float(k / side) + 0.5f) / float(side)) * 2.0f - 1.0f;
    } else {
      float r = std::sqrt((k + 0.5f) / kSoftShadowRays), phi = golden * float(k);
      d = r * glm::vec2(std::cos(phi), std::sin(phi));
    }
    LightSample ray = light;
    if (desc.type == SS_LIGHT_SUN) {
      ray.towardsLight = glm::normalize(w + d.x * a + d.y * b);
    } else {
      glm::vec3 target = p + w * light.distance + d.x * a + d.y * b;
      ray.distance = glm::length(target - p);
      ray.towardsLight = (target - p) / ray.distance;
    }
    seen += visible(rays, p, ng, ray, ignoredMesh) ? 1 : 0;
  }
  return float(seen) / kSoftShadowRays;
}

// TABULATED model: how far the light travels inside the object it entered at p before it leaves,
// as the GPU's exit-depth pass finds it (exit_depth.frag): the nearest surface facing away from
// the light along its ray beyond p, and its normal (*exitNormal); infinite (a half-space) when that
// surface is another object's, or there is none.
double exitDistance(const RayScene& rays, int mesh, const glm::vec3& p, const glm::vec3& ng,
                    const glm::vec3& towardsLight, glm::vec3* exitNormal) {
  glm::vec3 direction = -towardsLight;
  float eps = rays.epsilon();
  glm::vec3 origin = offsetOrigin(p, ng, direction, eps);
  double travelled = double(glm::length(origin - p));
  for (int step = 0; step < 64; ++step) {
    Hit hit = rays.intersect(origin, direction, 0.0f, std::numeric_limits<float>::infinity());
    if (!hit.valid()) break;
    travelled += hit.distance;
    const WorldMesh& m = rays.meshes()[size_t(hit.mesh)];
    glm::uvec3 t = m.triangle(hit.triangle);
    glm::vec3 n = interpolate(m.normals, t, {1.0f - hit.u - hit.v, hit.u, hit.v});
    if (glm::dot(n, towardsLight) < 0.0f) {
      *exitNormal = glm::dot(n, n) > 0.0f ? glm::normalize(n) : n;
      return hit.mesh == mesh ? travelled : std::numeric_limits<double>::infinity();
    }
    origin += direction * (hit.distance + eps);  // an entry: the exit pass does not see it
    travelled += eps;
  }
  return std::numeric_limits<double>::infinity();
}

// TABULATED model: the light that entered where `light` first meets the object of pixel point p
// and crossed the part to reach p (direct_lighting.frag: transmitted); n faces the camera.
// softEntries > 0 (the light's soft size; docs/SOFT_SHADOWS.md): opaque surfaces (`translucentHit`
// false) between the light and the entry are passed through, and the light reaching the entry is
// the share of the light's shape that no other object hides.
template <typename TranslucentHit>
glm::vec3 throughPart(const RayScene& rays, int mesh, const glm::vec3& p, const glm::vec3& n, const glm::vec3& view,
                      const SsLightDesc& light, const std::vector<glm::vec3>* worldDirections, const Profile& profile,
                      float sceneSize, float softEntries, const TranslucentHit& translucentHit) {
  LightSample ls = sampleLight(light, p);
  if (ls.irradiance == glm::vec3(0.0f)) return glm::vec3(0.0f);
  float far = std::isinf(ls.distance) ? sceneSize : ls.distance;
  glm::vec3 origin = p + ls.towardsLight * far;
  Hit hit = softEntries > 0.0f ? firstHit(rays, origin, -ls.towardsLight, 0.0f, far, translucentHit)
                               : rays.intersect(origin, -ls.towardsLight, 0.0f, far);
  if (!hit.valid() || hit.mesh != mesh) return glm::vec3(0.0f);
  double thickness = std::max(double(far) - double(hit.distance), 0.0);
  const WorldMesh& m = rays.meshes()[size_t(hit.mesh)];
  glm::uvec3 t = m.triangle(hit.triangle);
  glm::vec3 xe = interpolate(m.positions, t, {1.0f - hit.u - hit.v, hit.u, hit.v});
  glm::vec3 ne = glm::normalize(interpolate(m.normals, t, {1.0f - hit.u - hit.v, hit.u, hit.v}));
  LightSample entry = sampleLightOn(light, xe, ne);
  if (glm::dot(ne, entry.towardsLight) < 0.0f) ne = -ne;  // two-sided, as the irradiance buffer
  if (worldDirections) entry.irradiance *= worldWeight(*worldDirections, ne);
  double mu0 = std::clamp(double(glm::dot(ne, entry.towardsLight)), 0.0, 1.0);
  double mu = std::clamp(double(glm::dot(n, view)), 0.0, 1.0);
  thickness *= mu0;  // the slab's thickness along the entry's normal
  double scale = fresnelTransmittance(profile.eta, mu0) * mu0 * fresnelTransmittance(profile.eta, mu) *
                 slabLikeness(double(glm::dot(ne, n)));
  if (softEntries > 0.0f) {
    const glm::vec3 &a = m.positions[t.x], &b = m.positions[t.y], &c = m.positions[t.z];
    glm::vec3 ng = glm::normalize(glm::cross(b - a, c - a));
    scale *= double(softVisibility(rays, xe, ng, entry, light, softEntries, mesh));
  }
  glm::vec3 out(0.0f);
  for (int c = 0; c < 3; ++c) {
    double tau = thickness * profile.transport->extinction()[size_t(c)] * profile.mmPerUnit;
    out[c] = float(entry.irradiance[c] * scale * profile.transport->transmitted(c, tau, mu0, mu));
  }
  return out;
}

// The light entering translucent surfaces (step 1's flux): every light, its shadow rays, Fresnel,
// the TABULATED model's incidence factor and the colour texture's tint. REFERENCE's, and PRECOMPUTED's
// illumination map (EnteringLight).
struct EnteringContext {
  const Scene& scene;
  const RayScene& rays;
  const std::vector<MaterialEntry>& entries;
  std::vector<Profile> profiles;
  RenderLights rendered;
  std::vector<float> softSizes, entrySoftness;
  bool forwardShift;  // whether Entering::shift is computed (ReferenceOptions; PRECOMPUTED's relight)

  EnteringContext(const Scene& s, const RayScene& r, bool shift = false)
      : scene(s), rays(r), entries(s.denseMaterials()), rendered(renderLights(s)), forwardShift(shift) {
    for (size_t i = 0; i < entries.size(); ++i) profiles.emplace_back(entries[i], int(i));
    // Soft shadows: each light's disk, as the GPU's views have it (light_views.cpp).
    for (const SsLightDesc& l : rendered.lights) softSizes.push_back(lightSoftSize(l));
    // A soft light's shadow on the light entering translucent objects, as renderer.cpp draws it
    // (docs/SOFT_SHADOWS.md, "Translucent objects"): where another object can cast one, the
    // irradiance buffer holds translucent surfaces only, and each entry takes the share of the
    // light's shape that no other object hides.
    entrySoftness.assign(rendered.lights.size(), 0.0f);
    if (rays.meshes().size() > 1) entrySoftness = softSizes;
  }
  // The forward-shifted centre p + shift moved onto the surface of mesh `mesh` below (or above) it
  // along the entry's normal n (facing the light): on a curved part the point of the tangent plane
  // lies off the surface (above a convex part by about s^2 / 2R), where the profile's peak is
  // never reached (docs/TRANSPORT.md, "The entry's forward shift"). Kept where no surface of the
  // mesh lies within |shift| of it along n, or the one there is nearly edge-on to n. (The splatting
  // methods have no rays: splat.vert's surfaceDrop takes the surface as a paraboloid through a
  // point the light view sees.)
  glm::vec3 ontoSurface(uint32_t mesh, const glm::vec3& p, const glm::vec3& n, const glm::vec3& shift) const {
    float length = glm::length(shift);
    if (!(length > 0.0f)) return shift;
    glm::vec3 origin = p + shift + n * length;
    Hit h = rays.intersect(origin, -n, 0.0f, 2.0f * length);
    if (!h.valid() || uint32_t(h.mesh) != mesh) return shift;
    const WorldMesh& wm = rays.meshes()[size_t(h.mesh)];
    glm::uvec3 t = wm.triangle(h.triangle);
    glm::vec3 ng = glm::cross(wm.positions[t.y] - wm.positions[t.x], wm.positions[t.z] - wm.positions[t.x]);
    float area2 = glm::length(ng);
    if (!(area2 > 0.0f) || std::abs(glm::dot(ng, n)) < 0.25f * area2) return shift;  // as splat.vert's facing
    return origin - n * h.distance - p;
  }
  bool translucentHit(const Hit& h) const {
    return profiles[(*rays.meshes()[size_t(h.mesh)].materials)[h.triangle]].translucent;
  }
  // A light's sample at p, for a surface of normal n (either side: the world's weight takes the
  // side facing the light, as the shaders do).
  LightSample lightAt(size_t i, const glm::vec3& p, const glm::vec3& n) const {
    LightSample ls = sampleLightOn(rendered.lights[i], p, n);
    if (rendered.world[i])
      ls.irradiance *= worldWeight(rendered.worldDirections, glm::dot(n, ls.towardsLight) >= 0.0f ? n : -n);
    return ls;
  }

  // The flux through a cell of `area` at p on triangle `triangle` of ray mesh `mesh` (geometric
  // normal ng, shading normal ns, both unit) whose material entry is `base` (Fresnel, the
  // incidence factor) and whose point's entry is `point` (the tint at pointUv).
  Entering at(uint32_t mesh, uint32_t triangle, const glm::vec3& p, const glm::vec3& ng, const glm::vec3& ns,
              float area, uint32_t base, uint32_t point, const glm::vec2& pointUv) const {
    (void)triangle;
    const Profile& profile = profiles[base];  // Fresnel: the same for every entry
    const std::vector<SsLightDesc>& lights = rendered.lights;
    Entering out;
    glm::vec3 flux(0.0f), fluxMu0(0.0f);
    out.normal = ns;
    bool facing = false;
    auto translucent = [this](const Hit& h) { return translucentHit(h); };
    for (size_t li = 0; li < lights.size(); ++li) {
      LightSample ls = lightAt(li, p, ns);
      float cosGeometric = std::abs(glm::dot(ng, ls.towardsLight));
      if (cosGeometric <= 0.0f || ls.irradiance == glm::vec3(0.0f)) continue;
      float cosShading = std::abs(glm::dot(ns, ls.towardsLight));  // two-sided, as Cycles
      float ft = float(fresnelTransmittance(profile.eta, cosShading));
      if (ft <= 0.0f) continue;
      float visibility = 1.0f;
      if (entrySoftness[li] > 0.0f) {
        // The irradiance buffer's depth test among translucent surfaces, from the light's centre;
        // then the share of the light's shape that no other object hides.
        float eps = rays.epsilon();
        float far = std::isinf(ls.distance) ? std::numeric_limits<float>::infinity()
                                            : std::max(ls.distance - 2.0f * eps, 0.0f);
        glm::vec3 origin = offsetOrigin(p, ng, ls.towardsLight, eps);
        if (firstHit(rays, origin, ls.towardsLight, 0.0f, far, translucent).valid()) continue;
        visibility = softVisibility(rays, p, ng, ls, lights[li], entrySoftness[li], int(mesh));
        if (visibility <= 0.0f) continue;
      } else if (!visible(rays, p, ng, ls)) {
        continue;
      }
      glm::vec3 lightFlux = ls.irradiance * (cosGeometric * ft * area * visibility);
      if (profile.transport) {  // the incidence factor, for the thickness the light crosses here
        if (!facing) out.normal = glm::dot(ns, ls.towardsLight) >= 0.0f ? ns : -ns, facing = true;
        // The slab's thickness along its normal (the light crossed it at cosShading), and how
        // slab-like the part is between entry and exit (transport_model.h: slabLikeness).
        glm::vec3 exitNormal(0.0f);
        double thickness = exitDistance(rays, int(mesh), p, ng, ls.towardsLight, &exitNormal) * cosShading;
        glm::vec3 entryNormal = glm::dot(ns, ls.towardsLight) >= 0.0f ? ns : -ns;
        double slab = std::isinf(thickness) ? 0.0 : slabLikeness(double(glm::dot(entryNormal, exitNormal)));
        for (int c = 0; c < 3; ++c) {
          double tau = thickness * profile.transport->extinction()[size_t(c)] * profile.mmPerUnit;
          double halfSpace = profile.transport->incidence(c, double(INFINITY), cosShading);
          double slabFactor = slab > 0.0 ? profile.transport->incidence(c, tau, cosShading) : halfSpace;
          lightFlux[c] *= float(slab * slabFactor + (1.0 - slab) * halfSpace);
        }
        fluxMu0 += lightFlux * cosShading;
        // The forward shift: the refracted beam's part along the surface (length sin theta_t) times
        // the mean distance along it of the first collision, in scene units.
        if (forwardShift) {
        glm::vec3 along = (-ls.towardsLight + cosShading * entryNormal) / profile.eta;
        double sin2 = std::min(double(glm::dot(along, along)), 1.0), muT = std::sqrt(1.0 - sin2);
        for (int c = 0; c < 3; ++c) {
          double extinction = profile.transport->extinction()[size_t(c)] * profile.mmPerUnit;
          double mfp = extinction > 0.0 ? 1.0 / extinction : 0.0;
          out.shift[c] += along * float(lightFlux[c] * profile.transport->beamCentroid(c, muT) * mfp);
        }
        }
      }
      flux += lightFlux;
    }
    for (int c = 0; c < 3; ++c) out.shift[c] = flux[c] > 0.0f ? out.shift[c] / flux[c] : glm::vec3(0.0f);
    if (forwardShift)  // each channel's centre onto the surface
      for (int c = 0; c < 3; ++c) out.shift[c] = ontoSurface(mesh, p, out.normal, out.shift[c]);
    // The colour texture's tint, sqrt(T) as the light enters (irradiance_buffer.frag).
    if (entries[point].color) {
      glm::vec3 root = glm::sqrt(entries[point].color.sample(pointUv));
      flux *= root, fluxMu0 *= root;
    }
    out.flux = flux, out.fluxMu0 = fluxMu0;
    return out;
  }
};

struct TriangleCells {
  uint32_t mesh, triangle, cuts;  // cuts x cuts cells
  size_t first;                   // index of its first sample in its object
};

}  // namespace

struct EnteringLight::Context : EnteringContext {
  using EnteringContext::EnteringContext;
};

EnteringLight::EnteringLight(const Scene& scene, const RayScene& rays, bool forwardShift)
    : context_(std::make_unique<Context>(scene, rays, forwardShift)) {}
EnteringLight::~EnteringLight() = default;

Entering EnteringLight::at(uint32_t mesh, uint32_t triangle, const glm::vec3& p, const glm::vec3& ng,
                           const glm::vec3& ns, float area, uint32_t base, uint32_t point,
                           const glm::vec2& pointUv) const {
  return context_->at(mesh, triangle, p, ng, ns, area, base, point, pointUv);
}

void ReferenceRenderer::render(const Scene& scene, const ReferenceOptions& options, int width, int height,
                               float* rgba, const ProgressFunction& progress, SsStats& stats) {
  auto frameStart = Clock::now();
  RayScene rays(scene);
  const auto& meshes = rays.meshes();
  const EnteringContext entering(scene, rays, options.forwardShift);
  const std::vector<MaterialEntry>& entries = entering.entries;
  const std::vector<Profile>& profiles = entering.profiles;
  // The entry of a point of triangle t at barycentric w (its UV's profile).
  auto entryAt = [&](const WorldMesh& m, uint32_t t, const glm::vec3& w) {
    uint32_t base = (*m.materials)[t];
    if (!entries[base].mapped() || !m.mesh->hasUvs()) return base;
    glm::uvec3 i = m.triangle(t);
    const std::vector<glm::vec2>& uv = m.mesh->cpuUvs;
    glm::vec2 at = w.x * uv[i.x] + w.y * uv[i.y] + w.z * uv[i.z];
    return uint32_t(entries[base].entryAt(&at));
  };
  const RenderLights& rendered = entering.rendered;
  const std::vector<SsLightDesc>& lights = rendered.lights;
  auto lightAt = [&](size_t i, const glm::vec3& p, const glm::vec3& n) { return entering.lightAt(i, p, n); };
  const std::vector<float>& softSizes = entering.softSizes;
  auto worldOf = [&](size_t i) { return rendered.world[i] ? &rendered.worldDirections : nullptr; };
  const std::vector<float>& entrySoftness = entering.entrySoftness;
  auto translucentHit = [&](const Hit& h) { return entering.translucentHit(h); };

  // 1. Cells: by area, at least one per triangle.
  double totalArea = 0.0;
  auto triangleArea = [&](const WorldMesh& m, uint32_t t) {
    glm::uvec3 i = m.triangle(t);
    return 0.5 * double(glm::length(glm::cross(m.positions[i.y] - m.positions[i.x], m.positions[i.z] - m.positions[i.x])));
  };
  for (const WorldMesh& m : meshes)
    for (uint32_t t = 0; t < m.mesh->triangleCount; ++t)
      if (profiles[(*m.materials)[t]].translucent) totalArea += triangleArea(m, t);
  double cellArea = totalArea / double(std::max<uint64_t>(options.samples, 1));
  std::vector<ObjectSamples> objects(meshes.size());
  std::vector<TriangleCells> cells;
  size_t totalSamples = 0;
  for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
    const WorldMesh& m = meshes[mi];
    size_t count = 0;
    for (uint32_t t = 0; t < m.mesh->triangleCount; ++t) {
      const Profile& profile = profiles[(*m.materials)[t]];
      if (!profile.translucent) continue;
      double area = triangleArea(m, t);
      if (!(area > 0.0)) continue;  // degenerate: no area, no flux
      uint32_t cuts = uint32_t(std::clamp(std::lround(std::sqrt(area / cellArea)), 1l, 4096l));
      cells.push_back({mi, t, cuts, count});
      count += size_t(cuts) * cuts;
      objects[mi].support = std::max(objects[mi].support, profile.support);
      const MaterialEntry& base = entries[(*m.materials)[t]];
      if (base.mapped())  // every profile the triangle may show
        for (int e = 0; e < base.profiles->profileCount(); ++e)
          objects[mi].support = std::max(objects[mi].support, profiles[size_t(base.base + e)].support);
    }
    totalSamples += count;
    if (totalSamples * sizeof(SurfaceSample) > (size_t(8) << 30))
      fail(SS_LIMIT_EXCEEDED, "REFERENCE: " + std::to_string(totalSamples) +
                                  " surface samples exceed the 8 GiB memory budget; lower reference_samples");
    objects[mi].samples.resize(count);
  }

  // 2. Irradiance of every cell from shadow rays (flux E dA through it).
  parallelFor(cells.size(), 64, [&](size_t begin, size_t end) {
    for (size_t ci = begin; ci < end; ++ci) {
      const TriangleCells& tc = cells[ci];
      const WorldMesh& m = meshes[tc.mesh];
      glm::uvec3 tri = m.triangle(tc.triangle);
      glm::vec3 p0 = m.positions[tri.x], e1 = m.positions[tri.y] - p0, e2 = m.positions[tri.z] - p0;
      glm::vec3 ng = glm::normalize(glm::cross(e1, e2));
      bool hasUvs = m.mesh->hasUvs();
      glm::vec2 uv0(0.0f), uv1(0.0f), uv2(0.0f);
      if (hasUvs) uv0 = m.mesh->cpuUvs[tri.x], uv1 = m.mesh->cpuUvs[tri.y], uv2 = m.mesh->cpuUvs[tri.z];
      float n = float(tc.cuts);
      float area = 0.5f * glm::length(glm::cross(e1, e2)) / (n * n);
      SurfaceSample* out = objects[tc.mesh].samples.data() + tc.first;
      auto at = [&](float i, float j) { return glm::vec2(i / n, j / n); };
      auto emit = [&](glm::vec2 a, glm::vec2 b, glm::vec2 c) {
        SurfaceSample& s = *out++;
        glm::vec2 centre = (a + b + c) / 3.0f;
        s.corners[0] = p0 + a.x * e1 + a.y * e2;
        s.corners[1] = p0 + b.x * e1 + b.y * e2;
        s.corners[2] = p0 + c.x * e1 + c.y * e2;
        s.position = p0 + centre.x * e1 + centre.y * e2;
        s.diameter = std::sqrt(std::max({glm::dot(s.corners[1] - s.corners[0], s.corners[1] - s.corners[0]),
                                         glm::dot(s.corners[2] - s.corners[1], s.corners[2] - s.corners[1]),
                                         glm::dot(s.corners[0] - s.corners[2], s.corners[0] - s.corners[2])}));
        s.area = 0.5f * glm::length(glm::cross(s.corners[1] - s.corners[0], s.corners[2] - s.corners[0]));
        s.material = entryAt(m, tc.triangle, {1.0f - centre.x - centre.y, centre.x, centre.y});
        s.base = (*m.materials)[tc.triangle];
        s.mapped = hasUvs && entries[s.base].mapped();
        if (s.mapped) {
          const glm::vec2 w[3] = {a, b, c};
          for (int k = 0; k < 3; ++k) s.uvs[k] = uv0 + w[k].x * (uv1 - uv0) + w[k].y * (uv2 - uv0);
        }
        glm::vec3 ns = interpolate(m.normals, tri, {1.0f - centre.x - centre.y, centre.x, centre.y});
        ns = glm::dot(ns, ns) > 0.0f ? glm::normalize(ns) : ng;
        glm::vec2 pointUv = uv0 + centre.x * (uv1 - uv0) + centre.y * (uv2 - uv0);
        Entering in = entering.at(tc.mesh, tc.triangle, s.position, ng, ns, area, (*m.materials)[tc.triangle],
                                  s.material, pointUv);
        glm::vec3 flux = in.flux, fluxMu0 = in.fluxMu0;
        s.normal = in.normal;
        for (int c = 0; c < 3; ++c) s.shift[c] = in.shift[c];
        s.shiftReach = std::max({glm::length(s.shift[0]), glm::length(s.shift[1]), glm::length(s.shift[2])});
        s.flux = flux;
        s.fluxMu0 = fluxMu0;
      };
      for (uint32_t i = 0; i < tc.cuts; ++i)
        for (uint32_t j = 0; i + j < tc.cuts; ++j) {
          emit(at(i, j), at(i + 1, j), at(i, j + 1));
          if (i + j + 2 <= tc.cuts) emit(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
  }, progress, 0.0, 0.1);
  for (ObjectSamples& o : objects)
    if (!o.samples.empty()) o.buildGrid();
  double samplesMs = msSince(frameStart);

  // 3. Camera rays, B(x_o) and shading, row by row.
  auto pixelsStart = Clock::now();
  const SsCameraDesc& camera = scene.camera();
  glm::mat4 clipToWorld = glm::inverse(glm::make_mat4(camera.view_to_clip) * glm::make_mat4(camera.world_to_view));
  glm::vec3 cameraPos = cameraPosition(camera), forward = cameraForward(camera);
  float sceneSize = 4.0f * std::max(scene.bounds(false).radius(), 1e-6f) +
                    glm::length(scene.bounds(false).center()) + 1.0f;  // past the scene from any point in it
  exitance_.assign(size_t(width) * height * 4, 0.0f);
  std::atomic<uint64_t> evaluationsTotal{0};
  // Anti-aliasing (docs/ANTIALIASING.md): each pixel's jittered samples, their mean.
  std::vector<glm::vec2> offsets;
  for (int s = 0; s < options.pixelSamples; ++s)
    offsets.push_back(options.firstSample + s == 0 ? glm::vec2(0.0f)
                                                   : pixelFilterOffset(options.firstSample + s, options.filterWidth));
  struct Shaded {
    glm::vec4 color, exitance;
  };
  parallelFor(size_t(height), 1, [&](size_t begin, size_t end) {
    uint64_t evaluations = 0;
    // The colour and exitance seen through the image point `ndc`.
    auto shade = [&](glm::vec2 ndc) -> Shaded {
      glm::vec4 exitance(0.0f);
      glm::vec4 nearH = clipToWorld * glm::vec4(ndc, -1.0f, 1.0f), farH = clipToWorld * glm::vec4(ndc, 1.0f, 1.0f);
      glm::vec3 nearP = glm::vec3(nearH) / nearH.w, farP = glm::vec3(farH) / farH.w;
      glm::vec3 direction = farP - nearP;
      float length = glm::length(direction);
      Hit hit = length > 0.0f ? rays.intersect(nearP, direction / length, 0.0f, length) : Hit{};
      if (!hit.valid()) {  // the environment along the ray, else the background colour
        if (scene.environment()) return Shaded{glm::vec4(scene.environment().radiance(direction), 1.0f), glm::vec4(0.0f)};
        return Shaded{options.background, glm::vec4(0.0f)};
      }
      const WorldMesh& m = meshes[size_t(hit.mesh)];
      glm::uvec3 tri = m.triangle(hit.triangle);
      glm::vec3 w(1.0f - hit.u - hit.v, hit.u, hit.v);
      glm::vec3 p = interpolate(m.positions, tri, w);
      glm::vec3 ng = glm::normalize(glm::cross(m.positions[tri.y] - m.positions[tri.x], m.positions[tri.z] - m.positions[tri.x]));
      glm::vec3 n = interpolate(m.normals, tri, w);
      n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : ng;
      glm::vec3 view = camera.orthographic ? -forward : glm::normalize(cameraPos - p);
      if (glm::dot(n, view) < 0.0f) n = -n;  // two-sided, as Cycles
      uint32_t entryIndex = entryAt(m, hit.triangle, w);
      const Profile& profile = profiles[entryIndex];
      if (profile.holdout) {  // a hole in the image, alpha 0 (final_shading.frag)
        return Shaded{glm::vec4(0.0f), glm::vec4(0.0f)};
      }
      // The textures (splatting_buffer.frag): the tint (opaque albedo) and the normal map's shading
      // normal ns, which shades; n places the light through and the exitance's side weight.
      const MaterialEntry& entry = entries[entryIndex];
      glm::vec2 cornerUvs[3] = {glm::vec2(0.0f), glm::vec2(0.0f), glm::vec2(0.0f)};
      if (m.mesh->hasUvs())
        for (int k = 0; k < 3; ++k) cornerUvs[k] = m.mesh->cpuUvs[tri[k]];
      glm::vec2 uv = w.x * cornerUvs[0] + w.y * cornerUvs[1] + w.z * cornerUvs[2];
      glm::vec3 tint = entry.color.sample(uv);
      glm::vec3 ns = n;
      if (entry.normal) {
        const glm::vec3 corners[3] = {m.positions[tri.x], m.positions[tri.y], m.positions[tri.z]};
        glm::vec3 tangent, bitangent;
        triangleTangents(corners, cornerUvs, tangent, bitangent);
        ns = perturbedNormal(entry.normal.sample(uv), entry.desc.normal_strength, n, tangent, bitangent);
      }

      glm::vec3 color(0.0f);
      for (size_t li = 0; li < lights.size(); ++li) {
        LightSample ls = lightAt(li, p, ns);
        float nl = glm::dot(ns, ls.towardsLight);
        if (glm::dot(n, ls.towardsLight) <= 0.0f || nl <= 0.0f || ls.irradiance == glm::vec3(0.0f)) continue;
        float soft = softSizes[li];
        float visibility = soft > 0.0f ? softVisibility(rays, p, ng, ls, lights[li], soft)
                                       : visible(rays, p, ng, ls) ? 1.0f : 0.0f;
        if (visibility <= 0.0f) continue;
        ls.irradiance *= visibility;
        glm::vec3 diffuse = profile.translucent ? glm::vec3(0.0f) : profile.baseColor * tint / float(M_PI);
        // The world's specular reflection is its remainder's, below (world_light.h).
        float specular = rendered.world[li] ? 0.0f
                                            : specularBrdf(ns, ls.towardsLight, view, profile.roughness, profile.specular);
        color += (diffuse + glm::vec3(specular)) * ls.irradiance * nl;
      }
      glm::vec3 mirrored = glm::reflect(-view, ns);
      float mu = std::max(glm::dot(ns, view), 0.0f);
      color += worldRemainder(rendered, mirrored) * specularAlbedo(profile.roughness, profile.specular, mu);
      glm::vec3 ambient = rendered.unshadowed ? worldRemainder(rendered, ns) : glm::vec3(0.0f);
      if (!profile.translucent) color += ambient * profile.baseColor * tint;
      if (profile.translucent) {
        glm::dvec4 b = objects[size_t(hit.mesh)].samples.empty()
                           ? glm::dvec4(0.0)
                           : exitanceAt(objects[size_t(hit.mesh)], p, n, profile, entries, profiles, evaluations);
        float ft = float(fresnelTransmittance(profile.eta, mu));
        glm::dvec3 exitFactor(1.0);
        double sum = b.x + b.y + b.z;
        if (profile.transport && sum > 0.0)
          for (int c = 0; c < 3; ++c) exitFactor[c] = profile.transport->exit(c, b.w / sum, mu);
        // The tint: sqrt(T) here as the light leaves; the light through a part and the world's
        // remainder, T (they entered close by, docs/TEXTURES.md).
        color += glm::vec3(glm::dvec3(b) * exitFactor) * (ft / float(M_PI)) * glm::sqrt(tint);
        if (profile.transport)
          for (size_t li = 0; li < lights.size(); ++li) {
            LightSample ls = sampleLight(lights[li], p);
            if (glm::dot(n, ls.towardsLight) > 0.0f && visible(rays, p, ng, ls)) continue;  // lit itself
            color += throughPart(rays, hit.mesh, p, n, view, lights[li], worldOf(li), profile, sceneSize,
                                 entrySoftness[li], translucentHit) *
                     tint;
          }
        if (rendered.unshadowed) {  // final_shading.frag's remainder
          glm::vec3 world = ambient * profile.world * ft * tint;
          if (profile.transport)
            for (int c = 0; c < 3; ++c) {
              double root = std::sqrt(std::max(1.0 - profile.transport->albedo()[size_t(c)], 0.0));
              world[c] *= float(1.0 - root * profile.transport->h(c, mu));
            }
          color += world;
        }
        exitance = glm::vec4(float(b.x), float(b.y), float(b.z), 1.0f);
      }
      return Shaded{glm::vec4(color, 1.0f), exitance};
    };
    for (size_t y = begin; y < end; ++y)
      for (int x = 0; x < width; ++x) {
        size_t pixel = y * size_t(width) + size_t(x);
        glm::vec4 color(0.0f), exitance(0.0f);
        for (glm::vec2 offset : offsets) {
          glm::vec2 ndc((float(x) + 0.5f + offset.x) / float(width) * 2.0f - 1.0f,
                        (float(y) + 0.5f + offset.y) / float(height) * 2.0f - 1.0f);
          Shaded shaded = shade(ndc);
          color += shaded.color, exitance += shaded.exitance;
        }
        float weight = 1.0f / float(offsets.size());
        for (int c = 0; c < 4; ++c) rgba[4 * pixel + size_t(c)] = color[c] * weight;
        for (int c = 0; c < 4; ++c) exitance_[4 * pixel + size_t(c)] = exitance[c] * weight;
      }
    evaluationsTotal += evaluations;
  }, progress, 0.1, 0.9);

  stats = SsStats{};
  stats.width = width;
  stats.height = height;
  stats.splat_count = totalSamples;
  stats.samples = options.pixelSamples;
  stats.kernel_evaluations = evaluationsTotal.load();
  stats.stage_ms[SS_STAGE_BUFFERS] = samplesMs;
  stats.stage_ms[SS_STAGE_SPLATTING] = msSince(pixelsStart);
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const float* o = rgba + 4 * i;
    if (!std::isfinite(o[0]) || !std::isfinite(o[1]) || !std::isfinite(o[2]) || !std::isfinite(o[3]))
      ++stats.nonfinite_pixels;
    const float* e = exitance_.data() + 4 * i;
    if (e[3] == 0.0f) continue;
    ++stats.translucent_pixels;
    if (std::isfinite(e[0] + e[1] + e[2]) && e[0] + e[1] + e[2] > 0.0f) ++stats.lit_translucent_pixels;
  }
  stats.frame_ms = msSince(frameStart);
}

}  // namespace subsplat
