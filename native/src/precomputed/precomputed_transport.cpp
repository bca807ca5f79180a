#include "precomputed/precomputed_transport.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>

#include "material/radial_table.h"
#include "material/profile_set.h"
#include "material/transport_model.h"
#include "reference/ray_scene.h"
#include "reference/reference_renderer.h"
#include "util/error.h"

namespace subsplat {

namespace {

// One dense entry's profile per channel, in millimetres; support and detail in scene units.
struct EntryProfile {
  bool translucent = false, tabulated = false;
  std::array<std::shared_ptr<const RadialProfile>, 3> channel;
  RadialTable table;  // the channels' P and energy within a radius, for the kernels' inner loops
  double mmPerUnit = 1.0;
  double support = 0.0;   // the radius keeping kSupportEnergy of every channel
  double detail = 0.0;    // the finest channel's half-energy radius
};

constexpr double kSupportEnergy = 0.999;

std::vector<EntryProfile> entryProfiles(const Scene& scene) {
  const std::vector<MaterialEntry>& entries = scene.denseMaterials();
  std::vector<EntryProfile> out(entries.size());
  for (size_t i = 0; i < entries.size(); ++i) {
    const MaterialEntry& e = entries[i];
    EntryProfile& p = out[i];
    if (!isTranslucent(e.desc) || e.desc.kind == SS_MATERIAL_HOLDOUT) continue;
    p.translucent = true;
    p.tabulated = e.transport != nullptr;
    p.mmPerUnit = e.desc.mm_per_unit;
    p.detail = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) {
      if (e.desc.kind == SS_MATERIAL_SUBEDIT)
        p.channel[size_t(c)] = std::make_shared<SegmentedProfile>(e.profiles->channel(int(i) - e.base, c));
      else
        p.channel[size_t(c)] = makeMediumProfile({e.desc.sigma_a[c], e.desc.sigma_s_prime[c], e.desc.eta},
                                                 e.desc.profile_model);
      const RadialProfile& profile = *p.channel[size_t(c)];
      if (profile.totalEnergy() <= 0.0) continue;
      p.support = std::max(p.support, profile.radiusForEnergy(kSupportEnergy) / p.mmPerUnit);
      p.detail = std::min(p.detail, profile.radiusForEnergy(0.5) / p.mmPerUnit);
    }
    if (!std::isfinite(p.detail)) p.detail = 0.0;
    // P from the table for the dipole's closed form only: TABULATED's and SubEdit's P are cut to
    // zero at their tables' ends, which a cubic through the knots smears (radial_table.h).
    const bool dipole = !p.tabulated && e.desc.kind != SS_MATERIAL_SUBEDIT;
    p.table = RadialTable({p.channel[0].get(), p.channel[1].get(), p.channel[2].get()}, dipole);
  }
  return out;
}

// P's mean over a cell of radius h around the source at distance r (mm, 1/mm^2), per channel: over
// the disk when nearer than h, over the ring from r - h to r + h when nearer than 8 h, else P(r)
// (the profiles' peak at r = 0, which a point value misses; REFERENCE's Profile::evaluate does the
// same).
glm::dvec3 cellMean(const RadialTable& p, double r, double h) {
  if (h > 0.0 && r < 8.0 * h) {
    double lo = std::max(r - h, 0.0), hi = r + h;
    if (r < h) lo = 0.0, hi = h;
    return (p.energyWithin(hi) - p.energyWithin(lo)) / (M_PI * (hi * hi - lo * lo));
  }
  return p.value(r);
}

// R_d from a source cell of `area` with profile `in` to a point at distance r with profile `out`,
// 1 / unit^2: sqrt(P_in P_out) between different profiles (eq. 8).
glm::vec3 transport(const EntryProfile& in, const EntryProfile& out, double r, double area) {
  double h = std::sqrt(std::max(area, 0.0) / M_PI);
  glm::dvec3 a = cellMean(in.table, r * in.mmPerUnit, h * in.mmPerUnit) * (in.mmPerUnit * in.mmPerUnit);
  if (&in != &out) {
    glm::dvec3 b = cellMean(out.table, r * out.mmPerUnit, h * out.mmPerUnit) * (out.mmPerUnit * out.mmPerUnit);
    a = glm::sqrt(glm::max(a, 0.0) * glm::max(b, 0.0));
  }
  return glm::vec3(a);
}

constexpr int kPolygonAngles = 24;  // rays across a polygon seen from outside it; 8 times that around

// The share of a unit flux spread over a convex polygon (corners in mm, relative to the receiver
// at the origin, either turn) that a profile sends to the origin: the energy of P over it, by angle,
// with P's energy within a radius (energyWithin) along each ray from where it enters the polygon to
// where it leaves: exact but for the angular sum.
glm::dvec3 polygonEnergy(const RadialTable& p, const glm::dvec2* corners, size_t count, double height) {
  double twice = 0.0;
  for (size_t k = 0; k < count; ++k) {
    const glm::dvec2 &a = corners[k], &b = corners[(k + 1) % count];
    twice += a.x * b.y - b.x * a.y;
  }
  if (!(std::abs(twice) > 0.0)) return glm::dvec3(0.0);
  const double turn = twice > 0.0 ? 1.0 : -1.0;
  // Inside: n . x <= c for every edge (n outward).
  glm::dvec2 normal[8];
  double bound[8];
  bool inside = true;
  for (size_t k = 0; k < count; ++k) {
    const glm::dvec2 &a = corners[k], &b = corners[(k + 1) % count];
    normal[k] = turn * glm::dvec2(b.y - a.y, a.x - b.x);
    bound[k] = glm::dot(normal[k], a);
    if (bound[k] < 0.0) inside = false;
  }
  const double h2 = height * height;
  auto through = [&](const glm::dvec2& d) {  // P's energy along the ray in direction d inside the polygon
    double t0 = 0.0, t1 = INFINITY;
    for (size_t k = 0; k < count; ++k) {
      double nd = glm::dot(normal[k], d);
      if (std::abs(nd) < 1e-300) {
        if (bound[k] < 0.0) return glm::dvec3(0.0);
        continue;
      }
      double t = bound[k] / nd;
      if (nd > 0.0) t1 = std::min(t1, t);
      else t0 = std::max(t0, t);
    }
    if (!(t1 > t0)) return glm::dvec3(0.0);
    return p.energyWithin(std::sqrt(t1 * t1 + h2)) -
           (t0 > 0.0 || h2 > 0.0 ? p.energyWithin(std::sqrt(t0 * t0 + h2)) : glm::dvec3(0.0));
  };
  if (inside) {
    static const std::array<glm::dvec2, 8 * kPolygonAngles> around = [] {
      std::array<glm::dvec2, 8 * kPolygonAngles> d;
      for (size_t k = 0; k < d.size(); ++k) {
        const double theta = (double(k) + 0.5) / double(d.size()) * 2.0 * M_PI;
        d[k] = glm::dvec2(std::cos(theta), std::sin(theta));
      }
      return d;
    }();
    glm::dvec3 sum(0.0);
    for (const glm::dvec2& d : around) sum += through(d);
    return sum / double(around.size());
  }
  double lo = INFINITY, hi = -INFINITY, base = std::atan2(corners[0].y, corners[0].x);
  for (size_t k = 0; k < count; ++k) {
    double a = std::remainder(std::atan2(corners[k].y, corners[k].x) - base, 2.0 * M_PI);
    lo = std::min(lo, a), hi = std::max(hi, a);
  }
  glm::dvec3 sum(0.0);
  const double step = (hi - lo) / kPolygonAngles, first = base + lo + 0.5 * step;
  const glm::dvec2 rotation(std::cos(step), std::sin(step));  // each ray's direction is the last one's turned by step
  glm::dvec2 d(std::cos(first), std::sin(first));
  for (int k = 0; k < kPolygonAngles; ++k) {
    sum += through(d);
    d = glm::dvec2(d.x * rotation.x - d.y * rotation.y, d.x * rotation.y + d.y * rotation.x);
  }
  return sum * step / (2.0 * M_PI);
}

// R_d from a source texel to a receiver near it, 1 / unit^2: the profile's energy over each of the
// texel's parts (Atlas::parts: a part at the edge of a chart is not the square of its area), in the
// plane of the part's triangle, the profile at the 3D distance from the receiver (its height above
// the plane taken into each ray's distances), over the part's area, weighted by its share of the
// texel's; sqrt(K_in K_out) between different profiles.
glm::vec3 nearTransport(const EntryProfile& in, const EntryProfile& out, const Atlas& atlas, size_t texelIndex,
                        const WorldMesh& wm, const glm::vec3& receiver) {
  const uint32_t first = atlas.partStart[texelIndex], last = atlas.partStart[texelIndex + 1];
  constexpr size_t kMaxCorners = 8;
  const bool pair = &in != &out;
  glm::dvec3 sums[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  glm::dvec2 corners[kMaxCorners], scaled[kMaxCorners];
  for (uint32_t p = first; p < last; ++p) {
    const Atlas::SourcePart& part = atlas.parts[p];
    // The part's corners on its triangle (world units, in the triangle's plane around the receiver).
    const glm::uvec3 v = wm.triangle(part.triangle);
    const glm::dvec3 p0(wm.positions[v.x]), p1(wm.positions[v.y]), p2(wm.positions[v.z]);
    const glm::dvec3 normal = glm::cross(p1 - p0, p2 - p0);
    if (!(glm::dot(normal, normal) > 0.0)) continue;
    const glm::dvec3 e1 = glm::normalize(p1 - p0), e2 = glm::normalize(glm::cross(normal, e1));
    const glm::vec2* t = &atlas.cornerTexel[3 * size_t(part.triangle)];
    const glm::dvec2 a(t[0]), b(t[1]), c(t[2]);
    const double d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (!(std::abs(d) > 0.0)) continue;
    double twice = 0.0, height = 0.0;  // the receiver's above the plane
    for (uint32_t k = 0; k < part.cornerCount && k < kMaxCorners; ++k) {
      glm::dvec2 q(atlas.partCorners[part.corners + k]);
      double w1 = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
      double w2 = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
      glm::dvec3 x = (1.0 - w1 - w2) * p0 + w1 * p1 + w2 * p2 - glm::dvec3(receiver);
      corners[k] = glm::dvec2(glm::dot(x, e1), glm::dot(x, e2));
      if (k == 0) height = std::abs(glm::dot(x, glm::normalize(normal)));
    }
    const size_t count = std::min<size_t>(part.cornerCount, kMaxCorners);
    for (size_t k = 0; k < count; ++k) {
      const glm::dvec2 &u = corners[k], &w = corners[(k + 1) % count];
      twice += u.x * w.y - w.x * u.y;
    }
    const double area = 0.5 * std::abs(twice);  // world units^2
    if (!(area > 0.0)) continue;
    for (int side = 0; side < (pair ? 2 : 1); ++side) {
      const EntryProfile& profile = side == 0 ? in : out;
      for (size_t k = 0; k < count; ++k) scaled[k] = corners[k] * profile.mmPerUnit;
      sums[side] += double(part.share) / area * polygonEnergy(profile.table, scaled, count, height * profile.mmPerUnit);
    }
  }
  glm::vec3 k(0.0f);
  for (int ch = 0; ch < 3; ++ch)
    k[ch] = float(pair ? std::sqrt(std::max(sums[0][ch], 0.0) * std::max(sums[1][ch], 0.0)) : sums[0][ch]);
  return k;
}

// Sources nearer than this many texels are integrated over their parts (nearTransport).
constexpr double kNearTexels = 1.5;
// The atlas's border: receivers around each chart, for the display's bilinear lookups (the local
// response gathers its sources in 3D, across charts, so the border carries no light of its own).
constexpr int kBorderTexels = 3;
// Vertex pairs nearer than this many local ranges take the hats' mean (Galerkin) factors.
constexpr double kGalerkinRanges = 1.5;
// The factors take the profile no nearer than this share of the local range: its peak is the
// local kernels' (which hold R_d less the global response, so the sum within the local range is
// the same), and the vertices' exitance, interpolated over triangles, carries only the smooth
// remainder. With the peak in them, hats that overlap (neighbouring vertices of long triangles)
// brought a short profile's near light to receivers past the local range: stripes along a rod's
// vertex lines (docs/PRECOMPUTED.md, "Held-out scenes"). Chosen on the calibration set.
constexpr double kFactorNearest = 0.25;
// The direct weights' least squares: ridge of this share of the normal matrix's mean diagonal.
constexpr double kRidge = 0.05;

// Solves m x = b in place for `columns` right-hand sides (b: column after column, n each), m
// symmetric positive definite n x n, row by row (Cholesky; m is overwritten).
void solveSymmetric(std::vector<double>& m, size_t n, std::vector<double>& b, int columns) {
  for (size_t j = 0; j < n; ++j) {
    double d = m[j * n + j];
    for (size_t k = 0; k < j; ++k) d -= m[j * n + k] * m[j * n + k];
    d = std::sqrt(std::max(d, 1e-300));
    m[j * n + j] = d;
    for (size_t i = j + 1; i < n; ++i) {
      double v = m[i * n + j];
      for (size_t k = 0; k < j; ++k) v -= m[i * n + k] * m[j * n + k];
      m[i * n + j] = v / d;
    }
  }
  for (int c = 0; c < columns; ++c) {
    double* x = b.data() + size_t(c) * n;
    for (size_t i = 0; i < n; ++i) {  // L y = b
      for (size_t k = 0; k < i; ++k) x[i] -= m[i * n + k] * x[k];
      x[i] /= m[i * n + i];
    }
    for (size_t i = n; i-- > 0;) {  // L^T x = y
      for (size_t k = i + 1; k < n; ++k) x[i] -= m[k * n + i] * x[k];
      x[i] /= m[i * n + i];
    }
  }
}

uint64_t fnv(uint64_t h, const void* data, size_t bytes) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

// A texel's point: position, normal (unit), profile entry, area, its triangle's vertices and weights
// (a receiver's); a source's vertices are Object::sourceVertex[first] .. [first + count].
struct TexelPoint {
  glm::vec3 position{0.0f}, normal{0.0f}, geometricNormal{0.0f};
  uint32_t triangle = 0, base = 0, entry = 0;
  float area = 0.0f;
  glm::uvec3 vertices{0u};
  glm::vec3 beta{0.0f};
  glm::vec2 uv{0.0f};
  uint32_t first = 0, count = 0;
  uint32_t texel = 0;  // its atlas texel
};

// A point of a triangle of a world mesh at barycentric coordinates w: position, geometric and
// shading normals (unit), the triangle's material, the UV and the profile entry there.
struct MeshPoint {
  glm::vec3 position{0.0f}, geometricNormal{0.0f}, normal{0.0f};
  uint32_t base = 0, entry = 0;
  glm::vec2 uv{0.0f};
};
MeshPoint meshPoint(const WorldMesh& wm, const std::vector<MaterialEntry>& entries, uint32_t triangle, const glm::vec3& w) {
  const Mesh& mesh = *wm.mesh;
  const glm::uvec3 v = wm.triangle(triangle);
  MeshPoint p;
  p.position = w.x * wm.positions[v.x] + w.y * wm.positions[v.y] + w.z * wm.positions[v.z];
  const glm::vec3 n = w.x * wm.normals[v.x] + w.y * wm.normals[v.y] + w.z * wm.normals[v.z];
  p.geometricNormal = glm::normalize(glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x]));
  p.normal = glm::dot(n, n) > 0.0f ? glm::normalize(n) : p.geometricNormal;
  p.base = (*wm.materials)[triangle];
  if (mesh.hasUvs()) p.uv = w.x * mesh.cpuUvs[v.x] + w.y * mesh.cpuUvs[v.y] + w.z * mesh.cpuUvs[v.z];
  p.entry = uint32_t(entries[p.base].entryAt(mesh.hasUvs() ? &p.uv : nullptr));
  return p;
}

// Points sorted into a uniform grid, for the neighbours within a radius.
class PointGrid {
 public:
  PointGrid(const std::vector<glm::vec3>& points, double cell) : points_(points) {
    for (const glm::vec3& p : points) bounds_.extend(p);
    cell_ = float(std::max(cell, 1e-9));
    glm::vec3 extent = glm::max(bounds_.hi - bounds_.lo, glm::vec3(1e-6f));
    while (double(extent.x / cell_ + 1) * (extent.y / cell_ + 1) * (extent.z / cell_ + 1) > 4.0e6) cell_ *= 1.5f;
    dims_ = glm::ivec3(extent / cell_) + 1;
    start_.assign(size_t(dims_.x) * size_t(dims_.y) * size_t(dims_.z) + 1, 0);
    sorted_.resize(points.size());
    for (const glm::vec3& p : points) ++start_[index(cellOf(p)) + 1];
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) sorted_[fill[index(cellOf(points[i]))]++] = uint32_t(i);
  }
  // f(i, distance) for every point i within `radius` of p (in the grid's order: deterministic).
  template <typename F>
  void within(const glm::vec3& p, double radius, const F& f) const {
    if (points_.empty()) return;
    glm::ivec3 lo = cellOf(p - glm::vec3(float(radius))), hi = cellOf(p + glm::vec3(float(radius)));
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          size_t c = index({x, y, z});
          for (uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
            uint32_t i = sorted_[k];
            double d = double(glm::length(points_[i] - p));
            if (d < radius) f(i, d);
          }
        }
  }

 private:
  glm::ivec3 cellOf(const glm::vec3& p) const {
    return glm::clamp(glm::ivec3(glm::floor((p - bounds_.lo) / cell_)), glm::ivec3(0), dims_ - 1);
  }
  size_t index(glm::ivec3 c) const { return (size_t(c.z) * size_t(dims_.y) + size_t(c.y)) * size_t(dims_.x) + size_t(c.x); }
  const std::vector<glm::vec3>& points_;
  Bounds bounds_;
  float cell_ = 1.0f;
  glm::ivec3 dims_{1};
  std::vector<uint32_t> start_, sorted_;
};

}  // namespace

PrecomputedTransport::PrecomputedTransport() = default;
PrecomputedTransport::~PrecomputedTransport() = default;

namespace {

// An atlas's own memory: its texels' records and the charts' and triangles' tables.
size_t atlasBytes(const Atlas& atlas) {
  return atlas.texels.size() * sizeof(AtlasTexel) + atlas.rects.size() * sizeof(Atlas::Rect) +
         atlas.chartOfTriangle.size() * 4 +
         atlas.cornerTexel.size() * sizeof(glm::vec2) + atlas.partStart.size() * 4 +
         atlas.parts.size() * sizeof(Atlas::SourcePart) + atlas.partCorners.size() * sizeof(glm::vec2);
}

// What an object holds besides its kernels' taps and its factors, with `active` texels: the atlas,
// per texel its index, local response and (active ones) kernel start, index and source start, per
// source vertex its index, share and direct weight, per vertex its position and global response, per
// triangle corner its vertex.
size_t recordBytes(const Atlas& atlas, size_t active, size_t sourceVertices, size_t vertices, size_t corners) {
  return atlasBytes(atlas) + atlas.texels.size() * (4 + sizeof(glm::vec4)) + active * (4 + 4 + 4) + 8 +
         sourceVertices * (4 + 4 + sizeof(glm::vec3)) + vertices * (sizeof(glm::vec3) + sizeof(glm::vec4)) +
         corners * 4;
}

}  // namespace

size_t PrecomputedTransport::Object::bytes() const {
  return kernelSource.size() * 4 + kernelWeight.size() * sizeof(glm::vec3) + factor.size() * sizeof(glm::vec3) +
         column.size() * 4 + rowStart.size() * 4 +
         recordBytes(atlas, active.size(), sourceVertex.size(), vertexPositions.size(), vertexOfCorner.size());
}

size_t PrecomputedTransport::bytes() const {
  size_t total = 0;
  for (const Object& o : objects_) total += o.bytes();
  return total;
}

PrecomputationSize choosePrecomputation(double area, double edge, double support, double detail, size_t maxBytes) {
  PrecomputationSize size;
  size.edge = float(edge);
  size.detail = float(detail);
  double local = std::min(PrecomputedTransport::kLocalEdges * edge, support);
  if (!(local > 0.0)) local = std::max(edge, 1e-9);
  size.localRange = float(local);
  const double wanted = std::min({detail > 0.0 ? PrecomputedTransport::kDetailTexel * detail : local,
                                  local / PrecomputedTransport::kMinRadius, PrecomputedTransport::kEdgeTexel * edge});
  double texel = std::max(local / PrecomputedTransport::kMaxRadius, wanted);
  auto radiusFor = [&](double t) {
    return std::clamp(int(std::ceil(local / t - 1e-6)), PrecomputedTransport::kMinRadius, PrecomputedTransport::kMaxRadius);
  };
  // The texels at texel t (borders and packing about 80 % more than the surface), and each one's
  // kernel taps: the core texels within the local range, no more than the object's own past
  // kMaxRadius.
  auto texelsAt = [&](double t) { return 1.8 * area / (t * t) + 64.0; };
  auto tapsAt = [&](double t) {
    if (t * PrecomputedTransport::kMaxRadius >= local) {
      int radius = radiusFor(t);
      return M_PI * (radius + 0.5) * (radius + 0.5);
    }
    return std::min(M_PI * (local / t + 0.5) * (local / t + 0.5), texelsAt(t));
  };
  // A small object under a long profile: a finer texel than kMaxRadius allows is taken while all
  // its kernels' taps stay within kSmallObjectTaps (the object mostly within one local range: no
  // global branch to carry the light instead; docs/PRECOMPUTED.md, "What it is").
  for (double t = wanted; t < texel; t *= 1.05)
    if (texelsAt(t) * tapsAt(t) <= PrecomputedTransport::kSmallObjectTaps) {
      texel = t;
      break;
    }
  // Kernels, records and outputs of the texels within three quarters of the memory, the rest for
  // the factors.
  for (int step = 0; step < 200; ++step) {
    double texels = texelsAt(texel), taps = tapsAt(texel);
    double bytes = texels * (taps * PrecomputedTransport::kTapBytes + PrecomputedTransport::kTexelBytes);
    if (bytes <= 0.75 * double(maxBytes)) break;
    texel *= 1.15;
  }
  size.texel = float(texel);
  size.radius = radiusFor(texel);
  return size;
}

uint64_t PrecomputedTransport::hashMeshes(const Scene& scene) {
  uint64_t h = 1469598103934665603ull;
  for (const auto& [id, mesh] : scene.meshes()) {
    if (!mesh.translucent) continue;
    h = fnv(h, &id, sizeof id);  // (in object space: a rigid move is rigidMove's)
    h = fnv(h, mesh.cpuPositions.data(), mesh.cpuPositions.size() * sizeof(glm::vec3));
    h = fnv(h, mesh.cpuNormals.data(), mesh.cpuNormals.size() * sizeof(glm::vec3));
    h = fnv(h, mesh.cpuUvs.data(), mesh.cpuUvs.size() * sizeof(glm::vec2));
    h = fnv(h, mesh.cpuIndices.data(), mesh.cpuIndices.size() * sizeof(uint32_t));
    h = fnv(h, mesh.denseMaterials.data(), mesh.denseMaterials.size() * sizeof(uint32_t));
  }
  return h;
}

std::vector<double> PrecomputedTransport::signature(const Scene& scene) {
  std::vector<double> s;
  for (const MaterialEntry& e : scene.denseMaterials()) {
    const SsMaterialDesc& d = e.desc;
    s.insert(s.end(), {double(d.kind), double(d.eta), double(d.mm_per_unit), double(d.profile_model),
                       double(reinterpret_cast<uintptr_t>(e.profiles.get())), double(e.base)});
    for (int c = 0; c < 3; ++c) s.insert(s.end(), {double(d.sigma_a[c]), double(d.sigma_s_prime[c])});
  }
  return s;
}

std::vector<const void*> PrecomputedTransport::identity(const Scene& scene) {
  std::vector<const void*> out;
  for (const auto& [id, mesh] : scene.meshes()) {
    out.push_back(&mesh);
    out.push_back(mesh.cpuPositions.data());
    out.push_back(mesh.cpuIndices.data());
    out.push_back(mesh.denseMaterials.data());
    out.push_back(reinterpret_cast<const void*>(uintptr_t(mesh.triangleCount)));
    uint64_t h = fnv(1469598103934665603ull, mesh.cpuPositions.data(), mesh.cpuPositions.size() * sizeof(glm::vec3));
    h = fnv(h, &mesh.objectToWorld, sizeof mesh.objectToWorld);
    out.push_back(reinterpret_cast<const void*>(uintptr_t(h)));
  }
  return out;
}

std::vector<glm::mat4> PrecomputedTransport::transforms(const Scene& scene) {
  std::vector<glm::mat4> out;
  for (const auto& [id, mesh] : scene.meshes())
    if (mesh.translucent) out.push_back(mesh.objectToWorld);
  return out;
}

bool PrecomputedTransport::rigidMove(const glm::mat4& from, const glm::mat4& to) {
  // to = R from with R a rotation (and any translation): distances, angles and areas on the surface
  // are those the kernels and factors were computed for.
  glm::mat3 a = glm::mat3(to) * glm::inverse(glm::mat3(from));
  glm::mat3 gram = glm::transpose(a) * a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!(std::abs(gram[i][j] - (i == j ? 1.0f : 0.0f)) < 1e-5f)) return false;
  return glm::determinant(a) > 0.0f;
}

bool PrecomputedTransport::serves(const Scene& scene, bool ownUvs) const {
  if (!valid_ || ownUvs != ownUvs_ || meshHash_ != hashMeshes(scene) || materialSignature_ != signature(scene))
    return false;
  std::vector<glm::mat4> now = transforms(scene);
  if (now.size() != transforms_.size()) return false;
  for (size_t i = 0; i < now.size(); ++i)
    if (now[i] != transforms_[i] && !rigidMove(transforms_[i], now[i])) return false;
  return true;
}

void PrecomputedTransport::clear() {
  objects_.clear();
  valid_ = false;
  rays_.reset();
  rayIdentity_.clear();
}

void PrecomputedTransport::precompute(const Scene& scene, size_t maxBytes, const ProgressFunction& progress,
                                      bool ownUvs) {
  clear();
  ownUvs_ = ownUvs;
  rays_ = std::make_unique<RayScene>(scene);
  rayIdentity_ = identity(scene);
  const std::vector<MaterialEntry>& entries = scene.denseMaterials();
  const std::vector<EntryProfile> profiles = entryProfiles(scene);
  size_t used = 0;
  const auto& meshes = rays_->meshes();
  // The memory is shared between the objects by translucent area; what one leaves goes to the next.
  auto translucentArea = [&](const WorldMesh& wm) {
    double a = 0.0;
    for (size_t t = 0; t < wm.mesh->triangleCount; ++t) {
      if (!profiles[(*wm.materials)[t]].translucent) continue;
      glm::uvec3 v = wm.triangle(uint32_t(t));
      a += 0.5 * double(glm::length(glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x])));
    }
    return a;
  };
  double areaLeft = 0.0;
  for (const WorldMesh& wm : meshes) areaLeft += translucentArea(wm);
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    const WorldMesh& wm = meshes[mi];
    const Mesh& mesh = *wm.mesh;
    const size_t triangles = mesh.triangleCount;
    std::vector<char> include(triangles, 0);
    const double area = translucentArea(wm);
    double support = 0.0, detail = std::numeric_limits<double>::infinity();
    bool any = false;
    for (size_t t = 0; t < triangles; ++t) {
      uint32_t base = (*wm.materials)[t];
      if (!profiles[base].translucent) continue;
      include[t] = 1;
      any = true;
      int count = entries[base].mapped() ? entries[base].profiles->profileCount() : 1;
      for (int e = 0; e < count; ++e) {
        const EntryProfile& p = profiles[size_t(base) + size_t(e)];
        support = std::max(support, p.support);
        if (p.detail > 0.0) detail = std::min(detail, p.detail);
      }
    }
    if (!any) continue;
    if (!std::isfinite(detail)) detail = 0.0;
    objects_.emplace_back();
    Object& object = objects_.back();
    for (const auto& [id, m] : scene.meshes())
      if (&m == &mesh) object.objectId = id;
    object.rayMesh = int(mi);
    const auto objectStart = std::chrono::steady_clock::now();

    // Vertices: welded, over the atlas's triangles.
    std::vector<uint32_t> weld = weldVertices(wm.positions);
    std::vector<uint32_t> compact(wm.positions.size(), ~0u);
    object.vertexOfCorner.assign(3 * triangles, ~0u);
    std::vector<float> vertexArea;
    std::vector<glm::vec3> vertexNormal;
    std::vector<uint32_t> vertexEntry;
    std::vector<float> edges;
    for (size_t t = 0; t < triangles; ++t) {
      if (!include[t]) continue;
      glm::uvec3 v = wm.triangle(uint32_t(t));
      float triArea = 0.5f * glm::length(glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x]));
      for (int k = 0; k < 3; ++k) {
        uint32_t w = weld[v[k]];
        if (compact[w] == ~0u) {
          compact[w] = uint32_t(object.vertexPositions.size());
          object.vertexPositions.push_back(wm.positions[w]);
          vertexArea.push_back(0.0f);
          vertexNormal.push_back(glm::vec3(0.0f));
          glm::vec2 uv = mesh.hasUvs() ? mesh.cpuUvs[v[k]] : glm::vec2(0.0f);
          vertexEntry.push_back(uint32_t(entries[(*wm.materials)[t]].entryAt(mesh.hasUvs() ? &uv : nullptr)));
        }
        uint32_t c = compact[w];
        object.vertexOfCorner[3 * t + size_t(k)] = c;
        vertexArea[c] += triArea / 3.0f;
        vertexNormal[c] += wm.normals[v[k]];
        edges.push_back(glm::length(wm.positions[v[(k + 1) % 3]] - wm.positions[v[k]]));
      }
    }
    object.vertices = int(object.vertexPositions.size());
    // The hat functions' quadrature (midpoint rule, exact for quadratics over each triangle): a
    // source vertex's flux spread as its hat, at the midpoints of its edges; a receiving vertex's
    // value as the dual basis's projection (Lensch et al. eq. 5), +area/A* at the midpoints of its
    // edges and -area/A* at the opposite ones (A*: the star's area). Weights sum to 1.
    struct Sample {
      glm::vec3 p;
      float w;
    };
    std::vector<std::vector<Sample>> sourceSamples(object.vertexPositions.size()), receiverSamples(object.vertexPositions.size());
    for (size_t t = 0; t < triangles; ++t) {
      if (!include[t]) continue;
      glm::uvec3 v = wm.triangle(uint32_t(t));
      float triArea = 0.5f * glm::length(glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x]));
      if (!(triArea > 0.0f)) continue;
      for (int k = 0; k < 3; ++k) {
        uint32_t i = object.vertexOfCorner[3 * t + size_t(k)];
        glm::vec3 a = wm.positions[v[k]], b = wm.positions[v[(k + 1) % 3]], c = wm.positions[v[(k + 2) % 3]];
        float share = triArea / (3.0f * vertexArea[i]);  // area / A*
        sourceSamples[i].push_back({0.5f * (a + b), 0.5f * share});
        sourceSamples[i].push_back({0.5f * (a + c), 0.5f * share});
        receiverSamples[i].push_back({0.5f * (a + b), share});
        receiverSamples[i].push_back({0.5f * (a + c), share});
        receiverSamples[i].push_back({0.5f * (b + c), -share});
      }
    }
    // Midpoints shared by two triangles merged (sorted by position: deterministic).
    auto merge = [](std::vector<Sample>& samples) {
      std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) {
        return std::tie(a.p.x, a.p.y, a.p.z) < std::tie(b.p.x, b.p.y, b.p.z);
      });
      std::vector<Sample> merged;
      for (const Sample& x : samples)
        if (!merged.empty() && merged.back().p == x.p) merged.back().w += x.w;
        else merged.push_back(x);
      samples.swap(merged);
    };
    for (auto& v : sourceSamples) merge(v);
    for (auto& v : receiverSamples) merge(v);
    for (glm::vec3& n : vertexNormal) n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, 1);
    // The edge the local range is counted in: the mean, or half the 95th percentile where long
    // edges are common (a cylinder's sides), so that the local range covers most triangles' stars.
    double edge = 0.0;
    if (!edges.empty()) {
      double sum = 0.0;
      for (float e : edges) sum += double(e);
      std::nth_element(edges.begin(), edges.begin() + ptrdiff_t(edges.size() * 95 / 100), edges.end());
      edge = std::max(sum / double(edges.size()), 0.5 * double(edges[edges.size() * 95 / 100]));
    }

    // The texel and the local range, for this object's share of the memory left.
    const double share = areaLeft > 0.0 ? std::min(area / areaLeft, 1.0) : 1.0;
    areaLeft -= area;
    // An object that does not fit its share even at a coarser texel (many small charts: each takes
    // its borders whatever the texel; a bumpy mesh split at its creases), or whose factors alone
    // exceed it, takes all the memory still left instead (widen), from its own texel again; the
    // objects after it share what it leaves.
    const size_t poolLeft = maxBytes > used ? maxBytes - used : 0;
    const size_t left = size_t(double(poolLeft) * share);
    size_t objectLeft = left;
    object.size = choosePrecomputation(area, edge, support, detail, left);
    auto sideOf = [&](const EntryProfile& in, const glm::vec3& ni, const glm::vec3& no) {
      return in.tabulated ? float(sideWeight(double(glm::dot(ni, no)))) : 1.0f;
    };

    // Where the local range covers the profile's support, the local kernels are the whole response
    // and the global branch (factors and direct weights) has nothing to add: its interpolation over
    // triangles larger than the profile would spread light where none arrives.
    const bool globalBranch = object.size.localRange < 0.999 * support;
    // Global response: F by receiving vertex, sources within the support on a uniform grid.
    {
      const int V = object.vertices;
      PointGrid grid(object.vertexPositions, support);
      const double galerkinReach = object.size.localRange;
      const double nearest = kFactorNearest * galerkinReach;
      std::vector<std::vector<std::pair<uint32_t, glm::vec3>>> rows(static_cast<size_t>(V));
      parallelFor(size_t(V), 64, [&](size_t begin, size_t end) {
        for (size_t j = begin; j < end; ++j) {
          const glm::vec3& pj = object.vertexPositions[j];
          const EntryProfile& out = profiles[vertexEntry[j]];
          auto& row = rows[j];
          if (!globalBranch) continue;
          grid.within(pj, support, [&](uint32_t i, double r) {
            if (i == j) return;
            const EntryProfile& in = profiles[vertexEntry[i]];
            if (r >= std::max(in.support, out.support)) return;
            glm::vec3 f(0.0f);
            if (r < kGalerkinRanges * galerkinReach) {  // the hats' mean (convex profiles: interpolation overshoots)
              for (const auto& a : sourceSamples[i])
                for (const auto& b : receiverSamples[j])
                  f += a.w * b.w * transport(in, out, std::max(double(glm::length(a.p - b.p)), nearest), vertexArea[i] / 6.0);
            } else {
              f = transport(in, out, r, vertexArea[i]);
            }
            f *= sideOf(in, vertexNormal[i], vertexNormal[j]);
            if (double(std::max({f.x, f.y, f.z})) * vertexArea[j] < kFactorThreshold) return;
            row.emplace_back(i, f);
          });
          std::sort(row.begin(), row.end(), [](const auto& a, const auto& c) { return a.first < c.first; });
        }
      }, progress, 0.0, 0.2);
      object.rowStart.assign(size_t(V) + 1, 0);
      for (int j = 0; j < V; ++j) object.rowStart[size_t(j) + 1] = object.rowStart[size_t(j)] + uint32_t(rows[size_t(j)].size());
      size_t pairBytes = size_t(double(object.rowStart.back()) * kFactorBytes);
      if (pairBytes > left && pairBytes <= poolLeft) objectLeft = poolLeft;
      if (pairBytes > objectLeft)
        fail(SS_LIMIT_EXCEEDED, "PRECOMPUTED: object " + std::to_string(object.objectId) + " needs " +
                                    std::to_string(pairBytes >> 20) + " MiB of vertex-to-vertex factors (" +
                                    std::to_string(object.rowStart.back()) + " vertex pairs), more than the " +
                                    std::to_string(objectLeft >> 20) +
                                    " MiB of the memory budget left to it (fewer vertices, or another method)");
      object.column.reserve(object.rowStart.back());
      object.factor.reserve(object.rowStart.back());
      for (auto& row : rows)
        for (auto& [i, f] : row) object.column.push_back(i), object.factor.push_back(f);
    }
    const size_t factorBytes =
        object.column.size() * 4 + object.factor.size() * sizeof(glm::vec3) + object.rowStart.size() * 4;
    const size_t V = size_t(object.vertices);
    // F(i -> j), 0 where not kept.
    auto factorOf = [&](uint32_t i, uint32_t j) -> glm::vec3 {
      if (i == j) return glm::vec3(0.0f);
      auto first = object.column.begin() + object.rowStart[j], last = object.column.begin() + object.rowStart[size_t(j) + 1];
      auto it = std::lower_bound(first, last, i);
      return it != last && *it == i ? object.factor[size_t(it - object.column.begin())] : glm::vec3(0.0f);
    };
    // The global response at receiver q to unit flux at source s without the direct part, and the
    // direct part's basis: at q, the weights of s's vertices (count of them).
    auto globalAt = [&](const TexelPoint& s, const TexelPoint& q, glm::vec3& g0, double* basis) {
      g0 = glm::vec3(0.0f);
      std::fill(basis, basis + s.count, 0.0);
      for (int jj = 0; jj < 3; ++jj) {
        uint32_t j = q.vertices[jj];
        float bj = q.beta[jj];
        if (bj == 0.0f) continue;
        for (uint32_t e = 0; e < s.count; ++e) {
          uint32_t i = object.sourceVertex[s.first + e];
          if (i == j) basis[e] += double(bj);
          else g0 += bj * object.sourceBeta[s.first + e] * factorOf(i, j);
        }
      }
    };
    // The atlas, its texels' points and their kernels' taps, within the memory the factors left:
    // the taps (the core texels within the local range of each texel) are counted before any
    // kernel is computed, and a coarser texel is taken until everything fits.
    size_t atlasLeft = objectLeft > factorBytes ? objectLeft - factorBytes : 0;
    const PrecomputationSize chosen = object.size;
    auto widen = [&]() {
      if (objectLeft >= poolLeft) return false;
      objectLeft = poolLeft, atlasLeft = poolLeft > factorBytes ? poolLeft - factorBytes : 0;
      object.size = chosen;
      return true;
    };
    const Atlas& atlas = object.atlas;
    size_t active = 0;
    std::vector<TexelPoint> points, sources;
    std::vector<glm::vec3> corePositions;
    std::vector<uint32_t> coreActive;
    const double reach = object.size.localRange;
    double texel = 0.0, ringWidth = 0.0;
    std::unique_ptr<PointGrid> cores;
    for (int fit = 0;; ++fit) {
      // The atlas's borders and packing may take more texels than choosePrecomputation allowed for
      // (many small charts): a coarser texel then, until it fits (the kernels reach as far).
      double taps = 0.0;
      for (int attempt = 0;; ++attempt) {
        const int radius = object.size.radius;
        taps = M_PI * (radius + 0.5) * (radius + 0.5);
        size_t maxTexels = std::max<size_t>(size_t(double(atlasLeft) / (taps * kTapBytes + kTexelBytes)), 4096);
        try {
          object.atlas = buildAtlas(wm.positions, *wm.indices, include, object.size.texel, kBorderTexels, maxTexels,
                                    ownUvs && wm.mesh->hasUvs() ? &wm.mesh->cpuUvs : nullptr);
          break;
        } catch (const Error& e) {
          if (e.status() != SS_LIMIT_EXCEEDED) throw;
          if (attempt >= 16) {
            if (!widen()) throw;
            attempt = -1;
            continue;
          }
        }
        object.size.texel *= 1.25f;
        object.size.radius = std::clamp(int(std::ceil(object.size.localRange / object.size.texel - 1e-6f)), kMinRadius,
                                        kMaxRadius);
      }
      object.activeOf.assign(atlas.texels.size(), -1);
      object.active.clear();
      for (size_t i = 0; i < atlas.texels.size(); ++i)
        if (atlas.texels[i].kind != AtlasTexel::kEmpty) {
          object.activeOf[i] = int32_t(object.active.size());
          object.active.push_back(uint32_t(i));
        }
      active = object.active.size();
      // Each core texel's vertices: the hats integrated over its parts, merged by vertex.
      object.sourceStart.assign(active + 1, 0);
      object.sourceVertex.clear(), object.sourceBeta.clear();
      for (size_t a = 0; a < active; ++a) {
        const size_t texelIndex = object.active[a], first = object.sourceVertex.size();
        for (uint32_t p = atlas.partStart[texelIndex]; p < atlas.partStart[texelIndex + 1]; ++p) {
          const Atlas::SourcePart& part = atlas.parts[p];
          for (int k = 0; k < 3; ++k) {
            const uint32_t vertex = object.vertexOfCorner[3 * size_t(part.triangle) + size_t(k)];
            const float beta = part.share * part.barycentric[k];
            if (!(beta > 0.0f)) continue;
            size_t e = first;
            while (e < object.sourceVertex.size() && object.sourceVertex[e] != vertex) ++e;
            if (e == object.sourceVertex.size()) object.sourceVertex.push_back(vertex), object.sourceBeta.push_back(0.0f);
            object.sourceBeta[e] += beta;
          }
        }
        object.sourceStart[a + 1] = uint32_t(object.sourceVertex.size());
      }
      // Each active texel as a receiver (points: its centre) and as a source (sources: its core
      // part's centroid and area; area 0 where it has none).
      auto pointOn = [&](uint32_t triangle, const glm::vec3& w, float area) {
        TexelPoint p;
        const MeshPoint m = meshPoint(wm, entries, triangle, w);
        p.triangle = triangle;
        p.position = m.position, p.geometricNormal = m.geometricNormal, p.normal = m.normal;
        p.base = m.base, p.entry = m.entry, p.uv = m.uv;
        p.area = area;
        for (int k = 0; k < 3; ++k) p.vertices[k] = object.vertexOfCorner[3 * size_t(triangle) + size_t(k)];
        p.beta = w;
        return p;
      };
      points.assign(active, TexelPoint{}), sources.assign(active, TexelPoint{});
      for (size_t a = 0; a < active; ++a) {
        const AtlasTexel& tx = atlas.texels[object.active[a]];
        points[a] = pointOn(tx.triangle, tx.barycentric, 0.0f);
        if (tx.area > 0.0f) sources[a] = pointOn(tx.sourceTriangle, tx.sourceBarycentric, tx.area);
        sources[a].first = object.sourceStart[a], sources[a].count = object.sourceStart[a + 1] - object.sourceStart[a];
        sources[a].texel = object.active[a];
      }
      // The core texels (the sources: each surface point once) on a grid; the local range.
      corePositions.clear(), coreActive.clear();
      for (size_t a = 0; a < active; ++a)
        if (sources[a].area > 0.0f) corePositions.push_back(sources[a].position), coreActive.push_back(uint32_t(a));
      texel = atlas.texel, ringWidth = 1.5 * texel;
      cores = std::make_unique<PointGrid>(corePositions, reach + ringWidth);
      // What this object will hold (Object::bytes) once its kernels are computed.
      std::vector<uint32_t> counts(active, 0);
      parallelFor(active, 1024, [&](size_t begin, size_t end) {
        for (size_t a = begin; a < end; ++a) cores->within(points[a].position, reach, [&](uint32_t, double) { ++counts[a]; });
      }, ProgressFunction{}, 0.0, 0.0);
      uint64_t tapCount = 0;
      for (uint32_t c : counts) tapCount += c;
      const size_t bytes = size_t(double(tapCount) * kTapBytes) +
                           recordBytes(atlas, active, object.sourceVertex.size(), object.vertexPositions.size(),
                                       object.vertexOfCorner.size());
      if (bytes <= atlasLeft) break;
      if (fit >= 16 && widen()) {
        fit = -1;
        continue;
      }
      if (fit >= 16)
        fail(SS_LIMIT_EXCEEDED, "PRECOMPUTED: object " + std::to_string(object.objectId) + " needs " +
                                    std::to_string((bytes + factorBytes) >> 20) + " MiB of kernels, factors and atlas (" +
                                    std::to_string(tapCount) + " kernel taps over " + std::to_string(active) +
                                    " texels, " + std::to_string(object.rowStart.back()) + " vertex pairs), more than the " +
                                    std::to_string(objectLeft >> 20) +
                                    " MiB of the memory budget left to it (fewer vertices, or another method)");
      // Texels and taps each go as the texel's inverse square: the fourth root of the excess, a
      // little more.
      double step = std::clamp(1.01 * std::pow(double(bytes) / double(std::max<size_t>(atlasLeft, 1)), 0.25), 1.02, 1.5);
      object.size.texel = float(double(object.size.texel) * step);
      object.size.radius = std::clamp(int(std::ceil(object.size.localRange / object.size.texel - 1e-6f)), kMinRadius,
                                      kMaxRadius);
    }
    // R_d from source texel s to receiver t: over the source's parts when they are within
    // kNearTexels, else its mean over the source's disk or ring (cellMean).
    auto local = [&](const TexelPoint& s, const TexelPoint& t, double r) {
      const EntryProfile& in = profiles[s.entry];
      glm::vec3 k;
      if (r < kNearTexels * texel) {
        k = nearTransport(in, profiles[t.entry], atlas, s.texel, wm, t.position);
      } else {
        k = transport(in, profiles[t.entry], r, s.area);
      }
      return k * sideOf(in, s.normal, t.normal);
    };

    // Direct weights: fitted on the receivers just past the local range (within ringWidth).
    object.direct.assign(object.sourceVertex.size(), glm::vec3(0.0f));
    parallelFor(globalBranch ? coreActive.size() : 0, 256, [&](size_t begin, size_t end) {
      std::vector<double> m, rhs, basis;
      for (size_t ci = begin; ci < end; ++ci) {
        size_t a = coreActive[ci];
        const TexelPoint& s = sources[a];
        const size_t n = s.count;
        if (n == 0) continue;
        m.assign(n * n, 0.0), rhs.assign(3 * n, 0.0), basis.assign(n, 0.0);
        cores->within(s.position, reach + ringWidth, [&](uint32_t qi, double r) {
          if (r < reach) return;
          const TexelPoint& q = sources[coreActive[qi]];  // (a receiver there)
          glm::vec3 g0;
          globalAt(s, q, g0, basis.data());
          if (std::all_of(basis.begin(), basis.end(), [](double b) { return b == 0.0; })) return;
          glm::vec3 target = local(s, q, r);
          for (size_t x = 0; x < n; ++x) {
            if (basis[x] == 0.0) continue;
            for (size_t y = 0; y < n; ++y) m[x * n + y] += basis[x] * basis[y];
            for (int c = 0; c < 3; ++c) rhs[size_t(c) * n + x] += basis[x] * double(target[c] - g0[c]);
          }
        });
        double trace = 0.0;
        for (size_t x = 0; x < n; ++x) trace += m[x * n + x];
        if (!(trace > 0.0)) continue;
        for (size_t x = 0; x < n; ++x) m[x * n + x] += kRidge * trace / double(n);
        solveSymmetric(m, n, rhs, 3);
        for (size_t x = 0; x < n; ++x)
          for (int c = 0; c < 3; ++c) object.direct[s.first + x][c] = float(rhs[size_t(c) * n + x]);
      }
    }, progress, 0.2, 0.2);

    // Local kernels, per receiving texel: the core texels within the local range, across charts,
    // R_d less the global response to them.
    std::vector<std::vector<std::pair<uint32_t, glm::vec3>>> kernelLists(active);
    parallelFor(active, 1024, [&](size_t begin, size_t end) {
      // The factors into the receiver's three vertices, by source vertex (the rows of the last
      // receiving triangle scattered: consecutive texels mostly share a triangle).
      std::vector<std::array<glm::vec3, 3>> into(V, {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)});
      uint32_t scattered = ~0u;
      glm::uvec3 scatteredVertices(0u);
      for (size_t a = begin; a < end; ++a) {
        const TexelPoint& t = points[a];
        if (t.triangle != scattered) {
          if (scattered != ~0u)
            for (int jj = 0; jj < 3; ++jj)
              for (uint32_t k = object.rowStart[scatteredVertices[jj]]; k < object.rowStart[scatteredVertices[jj] + 1]; ++k)
                into[object.column[k]][size_t(jj)] = glm::vec3(0.0f);
          for (int jj = 0; jj < 3; ++jj)
            for (uint32_t k = object.rowStart[t.vertices[jj]]; k < object.rowStart[t.vertices[jj] + 1]; ++k)
              into[object.column[k]][size_t(jj)] = object.factor[k];
          scattered = t.triangle, scatteredVertices = t.vertices;
        }
        auto& list = kernelLists[a];
        cores->within(t.position, reach, [&](uint32_t si, double r) {
          size_t sa = coreActive[si];
          const TexelPoint& s = sources[sa];
          glm::vec3 k = local(s, t, r);
          // globalAt(s, t) with the scattered rows, and the direct part.
          for (int jj = 0; jj < 3; ++jj) {
            float bj = t.beta[jj];
            if (bj == 0.0f) continue;
            for (uint32_t e = s.first; e < s.first + s.count; ++e) {
              uint32_t i = object.sourceVertex[e];
              k -= bj * (i == t.vertices[jj] ? object.direct[e] : object.sourceBeta[e] * into[i][size_t(jj)]);
            }
          }
          list.emplace_back(uint32_t(sa), k);
        });
      }
    }, progress, 0.4, 0.6);
    object.kernelStart.assign(active + 1, 0);
    for (size_t a = 0; a < active; ++a) object.kernelStart[a + 1] = object.kernelStart[a] + uint32_t(kernelLists[a].size());
    object.kernelSource.reserve(object.kernelStart.back());
    object.kernelWeight.reserve(object.kernelStart.back());
    for (auto& list : kernelLists) {
      for (auto& [source, k] : list) object.kernelSource.push_back(source), object.kernelWeight.push_back(k);
      std::vector<std::pair<uint32_t, glm::vec3>>().swap(list);
    }
    object.local.assign(atlas.texels.size(), glm::vec4(0.0f));
    object.vertexExitance.assign(size_t(object.vertices), glm::vec4(0.0f));
    require(object.bytes() <= objectLeft, "PRECOMPUTED: an object holds more than its memory was checked for");
    used += object.bytes();
    object.precomputeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - objectStart).count();
  }
  meshHash_ = hashMeshes(scene);
  materialSignature_ = signature(scene);
  transforms_ = transforms(scene);
  valid_ = true;
}

namespace {

// The TABULATED model's forward shift in the illumination map (docs/PRECOMPUTED.md, "The forward
// shift"): the flux of each core texel, per channel, moves by its light's shift (shift[a][c], world
// units, along the surface) to the core texels around the point it reaches, found in the world (a
// texel-sized grid of the texels' points, so the move crosses charts as the surface does): each
// takes the tent weight max(0, 1 - d / h) of its distance d, h = 1.5 texels, among the texels whose
// normal faces the source's (not the far side of a thin part). Where none is near, the flux stays.
void moveByForwardShift(const WorldMesh& wm, const Atlas& atlas, const std::vector<uint32_t>& active,
                        const std::vector<std::array<glm::vec3, 3>>& shift, std::vector<glm::vec3>& flux,
                        std::vector<glm::vec3>& fluxMu0) {
  const size_t n = active.size();
  const float h = 1.5f * atlas.texel;
  std::vector<glm::vec3> point(n), normal(n);
  std::vector<float> area(n, 0.0f);
  std::vector<char> core(n, 0);
  Bounds bounds;
  for (size_t a = 0; a < n; ++a) {
    const AtlasTexel& tx = atlas.texels[active[a]];
    if (tx.area <= 0.0f || tx.triangle == AtlasTexel::kNone) continue;
    const glm::uvec3 v = wm.triangle(tx.triangle);
    const glm::vec3& w = tx.barycentric;
    point[a] = w.x * wm.positions[v.x] + w.y * wm.positions[v.y] + w.z * wm.positions[v.z];
    normal[a] = glm::cross(wm.positions[v.y] - wm.positions[v.x], wm.positions[v.z] - wm.positions[v.x]);
    core[a] = 1;
    area[a] = tx.area;
    bounds.extend(point[a]);
  }
  if (!(h > 0.0f) || bounds.lo.x > bounds.hi.x) return;
  // The grid: cells of side h (larger where that would make more than 4M), texels sorted by cell.
  float side = h;
  const glm::vec3 extent = glm::max(bounds.hi - bounds.lo, glm::vec3(1e-9f));
  while (double(extent.x / side + 1) * (extent.y / side + 1) * (extent.z / side + 1) > 4.0e6) side *= 1.5f;
  const glm::ivec3 dims = glm::ivec3(extent / side) + 1;
  auto cellOf = [&](const glm::vec3& p) {
    return glm::clamp(glm::ivec3(glm::floor((p - bounds.lo) / side)), glm::ivec3(0), dims - 1);
  };
  auto indexOf = [&](const glm::ivec3& c) { return (size_t(c.z) * size_t(dims.y) + size_t(c.y)) * size_t(dims.x) + size_t(c.x); };
  std::vector<uint32_t> cellStart(size_t(dims.x) * size_t(dims.y) * size_t(dims.z) + 1, 0), sorted;
  std::vector<uint32_t> cellOfTexel(n);
  for (size_t a = 0; a < n; ++a)
    if (core[a]) cellOfTexel[a] = uint32_t(indexOf(cellOf(point[a]))), ++cellStart[cellOfTexel[a] + 1];
  for (size_t c = 1; c < cellStart.size(); ++c) cellStart[c] += cellStart[c - 1];
  sorted.resize(cellStart.back());
  {
    std::vector<uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
    for (size_t a = 0; a < n; ++a)
      if (core[a]) sorted[fill[cellOfTexel[a]]++] = uint32_t(a);
  }
  std::vector<glm::vec3> movedFlux(n, glm::vec3(0.0f)), movedMu0(n, glm::vec3(0.0f));
  struct Near {
    uint32_t texel;
    glm::vec3 weight;
  };
  std::vector<Near> near;
  for (size_t a = 0; a < n; ++a) {
    const std::array<glm::vec3, 3>& s = shift[a];
    glm::vec3 total(0.0f);
    near.clear();
    if (core[a] && (s[0] != glm::vec3(0.0f) || s[1] != glm::vec3(0.0f) || s[2] != glm::vec3(0.0f))) {
      // One search for the three channels: around their targets' middle, as far as the farthest.
      const glm::vec3 target[3] = {point[a] + s[0], point[a] + s[1], point[a] + s[2]};
      const glm::vec3 middle = (target[0] + target[1] + target[2]) / 3.0f;
      const float reach = h + std::max({glm::distance(middle, target[0]), glm::distance(middle, target[1]),
                                        glm::distance(middle, target[2])});
      const glm::ivec3 lo = cellOf(middle - glm::vec3(reach)), hi = cellOf(middle + glm::vec3(reach));
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) {
            const size_t cell = indexOf({x, y, z});
            for (uint32_t i = cellStart[cell]; i < cellStart[cell + 1]; ++i) {
              const uint32_t b = sorted[i];
              if (glm::dot(normal[b], normal[a]) <= 0.0f) continue;
              glm::vec3 w(0.0f);
              for (int c = 0; c < 3; ++c) w[c] = std::max(0.0f, 1.0f - glm::distance(point[b], target[c]) / h) * area[b];
              if (w == glm::vec3(0.0f)) continue;
              near.push_back({b, w});
              total += w;
            }
          }
    }
    for (int c = 0; c < 3; ++c) {
      if (!(total[c] > 0.0f)) {
        movedFlux[a][c] += flux[a][c], movedMu0[a][c] += fluxMu0[a][c];
        continue;
      }
      for (const Near& m : near) {
        const float w = m.weight[c] / total[c];
        movedFlux[m.texel][c] += w * flux[a][c];
        movedMu0[m.texel][c] += w * fluxMu0[a][c];
      }
    }
  }
  flux.swap(movedFlux);
  fluxMu0.swap(movedMu0);
}

}  // namespace

void PrecomputedTransport::relight(const Scene& scene, const ProgressFunction& progress, bool forwardShift) {
  require(valid_, "PRECOMPUTED: nothing precomputed");
  if (identity(scene) != rayIdentity_) {  // the same translucent meshes; an occluder or a copy changed
    rays_ = std::make_unique<RayScene>(scene);
    rayIdentity_ = identity(scene);
    for (Object& object : objects_)
      for (size_t mi = 0; mi < rays_->meshes().size(); ++mi) {
        for (const auto& [id, m] : scene.meshes())
          if (id == object.objectId && rays_->meshes()[mi].mesh == &m) object.rayMesh = int(mi);
      }
  }
  const std::vector<MaterialEntry>& entries = scene.denseMaterials();
  EnteringLight light(scene, *rays_, forwardShift);
  // The exitance-weighted incidence cosine (alpha) is read by TABULATED materials only.
  const bool withMu0 = scene.tabulated();
  for (Object& object : objects_) {
    const WorldMesh& wm = rays_->meshes()[size_t(object.rayMesh)];
    const Atlas& atlas = object.atlas;
    const size_t active = object.active.size();
    // 1. The illumination map: the flux through every texel (and times mu0), the sum of its parts'.
    std::vector<glm::vec3> flux(active, glm::vec3(0.0f)), fluxMu0(active, glm::vec3(0.0f));
    const bool shifting = forwardShift && withMu0;
    std::vector<std::array<glm::vec3, 3>> shift(shifting ? active : 0);  // flux-weighted, then divided
    parallelFor(active, 256, [&](size_t begin, size_t end) {
      for (size_t a = begin; a < end; ++a) {
        const AtlasTexel& tx = atlas.texels[object.active[a]];
        if (tx.area <= 0.0f) continue;
        // At each part's centroid, on its own triangle: a texel across a bend or a shadow's edge
        // is not lit as the one point at its centroid.
        const size_t texelIndex = object.active[a];
        for (uint32_t pi = atlas.partStart[texelIndex]; pi < atlas.partStart[texelIndex + 1]; ++pi) {
          const Atlas::SourcePart& part = atlas.parts[pi];
          const MeshPoint m = meshPoint(wm, entries, part.triangle, part.barycentric);
          const Entering in = light.at(uint32_t(object.rayMesh), part.triangle, m.position, m.geometricNormal, m.normal,
                                       tx.area * part.share, m.base, m.entry, m.uv);
          flux[a] += in.flux, fluxMu0[a] += in.fluxMu0;
          if (shifting)
            for (int c = 0; c < 3; ++c) shift[a][size_t(c)] += in.flux[c] * in.shift[c];
        }
        if (shifting)
          for (int c = 0; c < 3; ++c) shift[a][size_t(c)] = flux[a][c] > 0.0f ? shift[a][size_t(c)] / flux[a][c] : glm::vec3(0.0f);
      }
    }, progress, 0.0, 0.5);
    if (shifting) moveByForwardShift(wm, atlas, object.active, shift, flux, fluxMu0);
    // 2. Vertex shares and the direct part, from the core texels.
    const size_t V = size_t(object.vertices);
    std::vector<glm::vec3> share(V, glm::vec3(0.0f)), shareMu0(V, glm::vec3(0.0f));
    std::vector<glm::vec3> direct(V, glm::vec3(0.0f)), directMu0(V, glm::vec3(0.0f));
    for (size_t a = 0; a < active; ++a)
      for (uint32_t e = object.sourceStart[a]; e < object.sourceStart[a + 1]; ++e) {
        const uint32_t vertex = object.sourceVertex[e];
        share[vertex] += object.sourceBeta[e] * flux[a];
        shareMu0[vertex] += object.sourceBeta[e] * fluxMu0[a];
        direct[vertex] += object.direct[e] * flux[a];
        directMu0[vertex] += object.direct[e] * fluxMu0[a];
      }
    // 3. The global response at the vertices.
    parallelFor(V, 256, [&](size_t begin, size_t end) {
      for (size_t j = begin; j < end; ++j) {
        glm::vec3 b = direct[j], bMu0 = directMu0[j];
        if (withMu0) {
          for (uint32_t k = object.rowStart[j]; k < object.rowStart[j + 1]; ++k) {
            b += object.factor[k] * share[object.column[k]];
            bMu0 += object.factor[k] * shareMu0[object.column[k]];
          }
        } else {
          for (uint32_t k = object.rowStart[j]; k < object.rowStart[j + 1]; ++k)
            b += object.factor[k] * share[object.column[k]];
        }
        object.vertexExitance[j] = glm::vec4(b, bMu0.x + bMu0.y + bMu0.z);
      }
    }, progress, 0.5, 0.1);
    // 4. The local response in the atlas.
    parallelFor(active, 256, [&](size_t begin, size_t end) {
      for (size_t a = begin; a < end; ++a) {
        glm::vec3 b(0.0f);
        float alpha = 0.0f;
        if (withMu0) {
          for (uint32_t k = object.kernelStart[a]; k < object.kernelStart[a + 1]; ++k) {
            const glm::vec3& w = object.kernelWeight[k];
            uint32_t s = object.kernelSource[k];
            b += w * flux[s];
            glm::vec3 m = w * fluxMu0[s];
            alpha += m.x + m.y + m.z;
          }
        } else {
          for (uint32_t k = object.kernelStart[a]; k < object.kernelStart[a + 1]; ++k)
            b += object.kernelWeight[k] * flux[object.kernelSource[k]];
        }
        object.local[object.active[a]] = glm::vec4(b, alpha);
      }
    }, progress, 0.6, 0.4);
  }
}

}  // namespace subsplat
