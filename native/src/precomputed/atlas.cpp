#include "precomputed/atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "util/error.h"

namespace subsplat {

std::vector<uint32_t> weldVertices(const std::vector<glm::vec3>& positions) {
  struct Key {
    uint32_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      return (size_t(k.x) * 73856093u) ^ (size_t(k.y) * 19349663u) ^ (size_t(k.z) * 83492791u);
    }
  };
  std::unordered_map<Key, uint32_t, Hash> first;
  first.reserve(positions.size());
  std::vector<uint32_t> weld(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    glm::vec3 p = positions[i] + glm::vec3(0.0f);  // -0 and +0 alike
    Key k{};
    std::memcpy(&k.x, &p.x, 4), std::memcpy(&k.y, &p.y, 4), std::memcpy(&k.z, &p.z, 4);
    weld[i] = first.emplace(k, uint32_t(i)).first->second;
  }
  return weld;
}

namespace {

// Barycentric coordinates of q in the 2D triangle a b c (any orientation); false when degenerate.
bool barycentric2(const glm::vec2& a, const glm::vec2& b, const glm::vec2& c, const glm::vec2& q, glm::vec3& w) {
  float d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
  if (!(std::abs(d) > 1e-12f)) return false;
  float w1 = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
  float w2 = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
  w = glm::vec3(1.0f - w1 - w2, w1, w2);
  return true;
}

// The part of a 2D triangle inside the unit square at (x, y) (Sutherland-Hodgman): its area,
// centroid and polygon (convex, at most 7 corners).
float clippedArea(const std::array<glm::vec2, 3>& q, float x, float y, glm::vec2& centroid, std::vector<glm::vec2>& poly) {
  std::vector<glm::vec2> next;
  poly.assign(q.begin(), q.end());
  auto clip = [&](int axis, float bound, bool keepBelow) {
    next.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      glm::vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
      bool ina = keepBelow ? a[axis] <= bound : a[axis] >= bound, inb = keepBelow ? b[axis] <= bound : b[axis] >= bound;
      if (ina) next.push_back(a);
      if (ina != inb) {
        float t = (bound - a[axis]) / (b[axis] - a[axis]);
        next.push_back(a + t * (b - a));
      }
    }
    poly.swap(next);
  };
  clip(0, x, false), clip(0, x + 1.0f, true), clip(1, y, false), clip(1, y + 1.0f, true);
  if (poly.size() < 3) return 0.0f;
  float twice = 0.0f;
  glm::vec2 c(0.0f);
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::vec2 &a = poly[i], &b = poly[(i + 1) % poly.size()];
    float cross = a.x * b.y - b.x * a.y;
    twice += cross;
    c += (a + b) * cross;
  }
  if (std::abs(twice) < 1e-12f) return 0.0f;
  centroid = c / (3.0f * twice);
  return 0.5f * std::abs(twice);
}

struct ChartBuild {
  std::vector<uint32_t> core;                    // triangles
  int island = -1;                               // the UV map's island it is, or -1 (made)
  glm::vec3 normal{0.0f}, u{0.0f}, v{0.0f};      // made: the mean normal, the projection's axes
  std::vector<std::pair<uint32_t, std::array<glm::vec2, 3>>> placed;  // core first, then border (unfolded)
  glm::vec2 lo{0.0f}, hi{0.0f};                  // core bounds in chart texels
  glm::ivec2 size{0};
};

// An island of the mesh's UV map: triangles joined across edges whose two ends have the same UVs
// on both sides.
struct Island {
  std::vector<uint32_t> triangles;
  float scale = 0.0f;  // world units per UV unit: the square root of their areas' ratio
  bool refused = false;
};

// The largest and smallest stretch of the map from a triangle's atlas coordinates q (texels) to its
// corners p (world units), in texels of `texel`: the singular values of the 2 x 2 map between the
// triangle's plane and the atlas. False when either is degenerate.
bool stretchOf(const std::array<glm::vec3, 3>& p, const std::array<glm::vec2, 3>& q, float texel, float& most,
               float& least) {
  glm::dvec3 e1 = glm::dvec3(p[1] - p[0]), e2 = glm::dvec3(p[2] - p[0]);
  double l1 = glm::length(e1);
  glm::dvec3 n = glm::cross(e1, e2);
  double ln = glm::length(n);
  if (!(l1 > 0.0) || !(ln > 0.0)) return false;
  glm::dvec3 x = e1 / l1, y = glm::cross(n / ln, x);
  glm::dmat2 world(glm::dot(e1, x), glm::dot(e1, y), glm::dot(e2, x), glm::dot(e2, y));  // columns
  glm::dmat2 atlas(glm::dvec2(q[1] - q[0]) * double(texel), glm::dvec2(q[2] - q[0]) * double(texel));
  double det = glm::determinant(atlas);
  if (!(std::abs(det) > 0.0)) return false;
  glm::dmat2 j = world * glm::inverse(atlas);
  double frob = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
  double d = std::abs(glm::determinant(j));
  double root = std::sqrt(std::max(frob * frob - 4.0 * d * d, 0.0));
  most = float(std::sqrt(0.5 * (frob + root))), least = float(std::sqrt(std::max(0.5 * (frob - root), 0.0)));
  return least > 0.0f;
}

}  // namespace

Atlas buildAtlas(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices,
                 const std::vector<char>& include, float texel, int border, size_t maxTexels,
                 const std::vector<glm::vec2>* uvs) {
  require(texel > 0.0f && std::isfinite(texel), "atlas: the texel size must be positive");
  require(border >= 0 && border <= 64, "atlas: the border must be in [0, 64] texels");
  const size_t triangles = indices.size() / 3;
  require(include.size() == triangles, "atlas: one include flag a triangle");
  require(!uvs || uvs->size() == positions.size(), "atlas: one UV a vertex");
  std::vector<uint32_t> weld = weldVertices(positions);
  auto corner = [&](size_t t, int k) { return weld[indices[3 * t + size_t(k)]]; };
  auto cornerPositions = [&](size_t t) {
    return std::array<glm::vec3, 3>{positions[indices[3 * t]], positions[indices[3 * t + 1]], positions[indices[3 * t + 2]]};
  };
  std::vector<glm::vec3> cross(triangles);
  std::vector<char> usable(triangles, 0);
  for (size_t t = 0; t < triangles; ++t) {
    const glm::vec3 &a = positions[indices[3 * t]], &b = positions[indices[3 * t + 1]], &c = positions[indices[3 * t + 2]];
    cross[t] = glm::cross(b - a, c - a);
    float len = glm::length(cross[t]);
    usable[t] = include[t] && len > 0.0f && std::isfinite(len);
  }
  // Edges over welded vertices: the triangles on each.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
  auto edgeKey = [](uint32_t a, uint32_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  for (size_t t = 0; t < triangles; ++t)
    if (usable[t])
      for (int k = 0; k < 3; ++k) edges[edgeKey(corner(t, k), corner(t, (k + 1) % 3))].push_back(uint32_t(t));

  // 0. The UV map's islands (cut at creases), each a chart of its own where it fits
  // (docs/PRECOMPUTED.md, "The mesh's own UV map"): its UVs scaled to world units, every triangle's stretch within
  // kMaxUvStretch either way, one winding, and (checked when rasterized, below) no texel covered
  // twice. The rest are charted as below.
  const float kCreaseCosine = std::cos(glm::radians(kCreaseDegrees));
  std::vector<Island> islands;
  std::vector<int> islandOf(triangles, -1);
  if (uvs) {
    const float tolerance = 1e-5f;  // (UVs are finite: ssSetMesh checks them)
    auto uvAt = [&](size_t t, uint32_t welded) {
      for (int k = 0; k < 3; ++k)
        if (corner(t, k) == welded) return (*uvs)[indices[3 * t + size_t(k)]];
      return glm::vec2(NAN);
    };
    for (size_t seed = 0; seed < triangles; ++seed) {
      if (!usable[seed] || islandOf[seed] >= 0) continue;
      const int id = int(islands.size());
      islands.emplace_back();
      std::deque<uint32_t> queue{uint32_t(seed)};
      islandOf[seed] = id;
      while (!queue.empty()) {
        uint32_t t = queue.front();
        queue.pop_front();
        islands.back().triangles.push_back(t);
        for (int k = 0; k < 3; ++k) {
          uint32_t a = corner(t, k), b = corner(t, (k + 1) % 3);
          for (uint32_t n : edges[edgeKey(a, b)]) {
            if (islandOf[n] >= 0) continue;
            if (glm::length(uvAt(t, a) - uvAt(n, a)) > tolerance || glm::length(uvAt(t, b) - uvAt(n, b)) > tolerance)
              continue;
            // Nor across a crease, as the border (step 3): the display's bilinear lookup would blend
            // the faces' exitances.
            if (glm::dot(cross[t], cross[n]) < kCreaseCosine * glm::length(cross[t]) * glm::length(cross[n])) continue;
            islandOf[n] = id;
            queue.push_back(n);
          }
        }
      }
    }
    for (Island& island : islands) {
      double world = 0.0, mapped = 0.0;
      int positive = 0, negative = 0;
      for (uint32_t t : island.triangles) {
        const glm::vec2 &a = (*uvs)[indices[3 * size_t(t)]], &b = (*uvs)[indices[3 * size_t(t) + 1]],
                        &c = (*uvs)[indices[3 * size_t(t) + 2]];
        double signedArea = 0.5 * (double(b.x - a.x) * double(c.y - a.y) - double(c.x - a.x) * double(b.y - a.y));
        (signedArea > 0.0 ? positive : negative) += 1;
        world += 0.5 * double(glm::length(cross[t])), mapped += std::abs(signedArea);
      }
      island.scale = float(std::sqrt(world / std::max(mapped, 1e-300)));
      island.refused = (positive > 0 && negative > 0) || !(mapped > 0.0) || !std::isfinite(island.scale);
      for (size_t i = 0; i < island.triangles.size() && !island.refused; ++i) {
        const size_t t = island.triangles[i];
        std::array<glm::vec2, 3> q;
        for (int k = 0; k < 3; ++k) q[size_t(k)] = (*uvs)[indices[3 * t + size_t(k)]] * (island.scale / texel);
        float most = 0.0f, least = 0.0f;
        island.refused = !stretchOf(cornerPositions(t), q, texel, most, least) || most > kMaxUvStretch ||
                         least < 1.0f / kMaxUvStretch;
      }
    }
  }

  // The charts (steps 1-5), again with the islands that overlap themselves refused.
  for (int round = 0;; ++round) {
    Atlas atlas;
    atlas.texel = texel;
    atlas.border = border;
    atlas.chartOfTriangle.assign(triangles, -1);
    atlas.cornerTexel.assign(3 * triangles, glm::vec2(0.0f));
    const float cosLimit = std::cos(glm::radians(kMaxDeviationDegrees));

    // 1. Charts: the islands that fit (laid out as their scaled UVs, step 2), then charts grown
    // over the rest (projected onto their mean normal, step 2).
    std::vector<ChartBuild> charts;
    for (size_t i = 0; i < islands.size(); ++i) {
      if (islands[i].refused) continue;
      const int id = int(charts.size());
      charts.emplace_back();
      charts.back().island = int(i);
      charts.back().core = islands[i].triangles;
      for (uint32_t t : islands[i].triangles) atlas.chartOfTriangle[t] = id;
      ++atlas.uvCharts;
    }
    for (const Island& island : islands) atlas.uvIslandsRefused += island.refused ? 1 : 0;
    for (size_t seed = 0; seed < triangles; ++seed) {
      if (!usable[seed] || atlas.chartOfTriangle[seed] >= 0) continue;
      int id = int(charts.size());
      charts.emplace_back();
      ChartBuild& chart = charts.back();
      glm::vec3 sum = cross[seed];
      std::deque<uint32_t> queue{uint32_t(seed)};
      atlas.chartOfTriangle[seed] = id;
      while (!queue.empty()) {
        uint32_t t = queue.front();
        queue.pop_front();
        chart.core.push_back(t);
        for (int k = 0; k < 3; ++k)
          for (uint32_t n : edges[edgeKey(corner(t, k), corner(t, (k + 1) % 3))]) {
            if (atlas.chartOfTriangle[n] >= 0) continue;
            if (glm::dot(glm::normalize(cross[n]), glm::normalize(sum)) < cosLimit) continue;
            atlas.chartOfTriangle[n] = id;
            sum += cross[n];
            queue.push_back(n);
          }
      }
      chart.normal = glm::normalize(sum);
      glm::vec3 axis = std::abs(chart.normal.x) < 0.6f   ? glm::vec3(1, 0, 0)
                       : std::abs(chart.normal.y) < 0.6f ? glm::vec3(0, 1, 0)
                                                         : glm::vec3(0, 0, 1);
      chart.u = glm::normalize(glm::cross(chart.normal, axis)), chart.v = glm::cross(chart.normal, chart.u);
    }

    // 2. Each chart in texels, turned to the least bounding box: a made chart projected onto the
    // plane of its mean normal, an island as its scaled UVs.
    for (size_t ci = 0; ci < charts.size(); ++ci) {
      ChartBuild& chart = charts[ci];
      std::vector<glm::vec2> points;
      for (size_t i = 0; i < chart.core.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          const uint32_t vertex = indices[3 * size_t(chart.core[i]) + size_t(k)];
          const glm::vec3& p = positions[vertex];
          points.push_back(chart.island < 0 ? glm::vec2(glm::dot(p, chart.u) / texel, glm::dot(p, chart.v) / texel)
                                            : (*uvs)[vertex] * islands[size_t(chart.island)].scale / texel);
        }
      float best = INFINITY, bestAngle = 0.0f;
      for (int step = 0; step < 90; ++step) {
        float a = glm::radians(float(step)), c = std::cos(a), s = std::sin(a);
        glm::vec2 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec2& p : points) {
          glm::vec2 r(c * p.x - s * p.y, s * p.x + c * p.y);
          lo = glm::min(lo, r), hi = glm::max(hi, r);
        }
        float area = (hi.x - lo.x + 1.0f) * (hi.y - lo.y + 1.0f);
        if (area < best) best = area, bestAngle = a;
      }
      const float c = std::cos(bestAngle), s = std::sin(bestAngle);
      if (chart.island < 0) {
        const glm::vec3 u = chart.u, v = chart.v;
        chart.u = c * u - s * v, chart.v = s * u + c * v;
      }
      glm::vec2 lo(INFINITY), hi(-INFINITY);
      for (size_t i = 0; i < chart.core.size(); ++i) {
        std::array<glm::vec2, 3> q;
        for (int k = 0; k < 3; ++k) {
          if (chart.island < 0) {
            const glm::vec3& p = positions[indices[3 * size_t(chart.core[i]) + size_t(k)]];
            q[size_t(k)] = glm::vec2(glm::dot(p, chart.u), glm::dot(p, chart.v)) / texel;
          } else {
            const glm::vec2& p = points[3 * i + size_t(k)];
            q[size_t(k)] = glm::vec2(c * p.x - s * p.y, s * p.x + c * p.y);
          }
          lo = glm::min(lo, q[size_t(k)]), hi = glm::max(hi, q[size_t(k)]);
        }
        chart.placed.emplace_back(chart.core[i], q);
      }
      // Chart texels: the core's bounds start at `border`.
      glm::vec2 shift = glm::vec2(float(border)) - glm::floor(lo);
      for (auto& [t, q] : chart.placed)
        for (glm::vec2& p : q) p += shift;
      chart.lo = lo + shift, chart.hi = hi + shift;
      chart.size = glm::ivec2(glm::ceil(chart.hi)) + border + 1;
    }

    // 3. Border: unfolded across shared edges, ring by ring, while they reach the rectangle, but not
    // across a crease (neighbouring faces more than kCreaseDegrees apart).
    for (size_t ci = 0; ci < charts.size(); ++ci) {
      ChartBuild& chart = charts[ci];
      std::unordered_map<uint32_t, size_t> placedAt;
      for (size_t i = 0; i < chart.placed.size(); ++i) placedAt[chart.placed[i].first] = i;
      const size_t limit = 64 * chart.core.size() + 4096;
      glm::vec2 rectLo(0.0f), rectHi(chart.size);
      for (size_t i = 0; i < chart.placed.size() && chart.placed.size() < limit; ++i) {
        uint32_t t = chart.placed[i].first;
        std::array<glm::vec2, 3> q = chart.placed[i].second;
        glm::vec2 qlo = glm::min(q[0], glm::min(q[1], q[2])), qhi = glm::max(q[0], glm::max(q[1], q[2]));
        if (qhi.x < rectLo.x || qhi.y < rectLo.y || qlo.x > rectHi.x || qlo.y > rectHi.y) continue;  // goes no further
        for (int k = 0; k < 3; ++k) {
          uint32_t a = corner(t, k), b = corner(t, (k + 1) % 3);
          glm::vec2 pa = q[size_t(k)], pb = q[size_t((k + 1) % 3)], pc = q[size_t((k + 2) % 3)];
          for (uint32_t n : edges[edgeKey(a, b)]) {
            if (placedAt.count(n) || atlas.chartOfTriangle[n] == int(ci)) continue;
            // Not across a crease: the face beyond it has an exitance of its own (a cylinder's lit
            // cap beside its side), which the display's bilinear lookup would blend into this face's
            // last half texel. Those texels take their nearest neighbour's point instead (below).
            if (glm::dot(cross[t], cross[n]) < kCreaseCosine * glm::length(cross[t]) * glm::length(cross[n])) continue;
            // n's corners: a and b where they are; its third placed across the edge from pc.
            int ka = -1, kb = -1, kc = -1;
            for (int j = 0; j < 3; ++j) {
              uint32_t w = corner(n, j);
              if (w == a && ka < 0) ka = j;
              else if (w == b && kb < 0) kb = j;
              else kc = j;
            }
            if (ka < 0 || kb < 0 || kc < 0) continue;
            glm::vec3 A = positions[indices[3 * size_t(n) + size_t(ka)]], B = positions[indices[3 * size_t(n) + size_t(kb)]];
            glm::vec3 C = positions[indices[3 * size_t(n) + size_t(kc)]];
            float d = glm::length(pb - pa);
            if (!(d > 0.0f)) continue;
            float la = glm::length(C - A) / texel, lb = glm::length(C - B) / texel;
            float x = (la * la - lb * lb + d * d) / (2.0f * d);
            float h = std::sqrt(std::max(la * la - x * x, 0.0f));
            glm::vec2 e = (pb - pa) / d, perp(-e.y, e.x);
            float side = glm::dot(pc - pa, perp) > 0.0f ? -1.0f : 1.0f;
            std::array<glm::vec2, 3> r;
            r[size_t(ka)] = pa, r[size_t(kb)] = pb, r[size_t(kc)] = pa + x * e + side * h * perp;
            placedAt[n] = chart.placed.size();
            chart.placed.emplace_back(n, r);
          }
        }
      }
    }

    // 4. Shelf packing, tallest first.
    std::vector<size_t> order(charts.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return charts[a].size.y > charts[b].size.y; });
    double total = 0.0;
    int widest = 1;
    for (const ChartBuild& c : charts) total += double(c.size.x) * c.size.y, widest = std::max(widest, c.size.x);
    int width = std::max(widest, int(std::ceil(std::sqrt(total) * 1.05)));
    atlas.rects.assign(charts.size(), Atlas::Rect{});
    int x = 0, y = 0, shelf = 0;
    for (size_t i : order) {
      const ChartBuild& c = charts[i];
      if (x + c.size.x > width) x = 0, y += shelf, shelf = 0;
      atlas.rects[i] = {glm::ivec2(x, y), c.size};
      x += c.size.x;
      shelf = std::max(shelf, c.size.y);
    }
    atlas.width = width;
    atlas.height = std::max(y + shelf, 1);
    atlas.charts = int(charts.size());
    if (double(atlas.width) * atlas.height > double(maxTexels))
      fail(SS_LIMIT_EXCEEDED, "PRECOMPUTED: the atlas needs " + std::to_string(atlas.width) + " x " +
                                  std::to_string(atlas.height) + " texels, more than " + std::to_string(maxTexels) +
                                  " (fewer triangles or a coarser texel)");
    atlas.texels.assign(size_t(atlas.width) * atlas.height, AtlasTexel{});

    // 5. Rasterization: the core's parts in each square (sources); the texel centres on the core,
    // then on the border, then the gaps' fillers (receivers).
    const float texelArea = texel * texel;
    std::vector<float> share(atlas.texels.size(), 0.0f);  // the part of the texel's source triangle
    std::vector<glm::vec3> moment(atlas.texels.size(), glm::vec3(0.0f));  // sum of parts' centroid x area, area
    std::vector<uint32_t> holder(atlas.texels.size(), AtlasTexel::kNone);
    std::vector<std::pair<size_t, Atlas::SourcePart>> parts;  // by texel index, then as rasterized
    std::vector<glm::vec2> polygon, polygons;                   // the parts' corners, in their order
    for (size_t ci = 0; ci < charts.size(); ++ci) {
      const ChartBuild& chart = charts[ci];
      const Atlas::Rect& rect = atlas.rects[ci];
      glm::vec2 offset(rect.origin);
      for (size_t i = 0; i < chart.placed.size(); ++i) {
        uint32_t t = chart.placed[i].first;
        const std::array<glm::vec2, 3>& q = chart.placed[i].second;
        bool core = i < chart.core.size();
        if (core)
          for (int k = 0; k < 3; ++k) atlas.cornerTexel[3 * size_t(t) + size_t(k)] = q[size_t(k)] + offset;
        // World area per atlas area (texels^2): texel^2 / cos for a projected chart, the island's
        // stretch for a UV chart (no more than ten times a texel's area per texel in either).
        float areaScale = 0.0f;
        if (chart.island < 0) {
          areaScale = texelArea / std::max(std::abs(glm::dot(glm::normalize(cross[t]), chart.normal)), 0.1f);
        } else {
          const float mapped = 0.5f * std::abs((q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y));
          const float world = 0.5f * glm::length(cross[t]);
          areaScale = world / std::max(mapped, 0.1f * world / texelArea);
        }
        glm::ivec2 lo = glm::max(glm::ivec2(glm::floor(glm::min(q[0], glm::min(q[1], q[2])))), glm::ivec2(0));
        glm::ivec2 hi = glm::min(glm::ivec2(glm::ceil(glm::max(q[0], glm::max(q[1], q[2])))), rect.size - 1);
        for (int ty = lo.y; ty <= hi.y; ++ty)
          for (int tx = lo.x; tx <= hi.x; ++tx) {
            size_t index = size_t(rect.origin.y + ty) * size_t(atlas.width) + size_t(rect.origin.x + tx);
            AtlasTexel& texelOut = atlas.texels[index];
            if (core) {
              glm::vec2 centroid;
              float part = clippedArea(q, float(tx), float(ty), centroid, polygon);
              glm::vec3 w;
              if (part > 0.0f && barycentric2(q[0], q[1], q[2], centroid, w)) {
                texelOut.area += part * areaScale;
                texelOut.chart = int(ci);
                moment[index] += glm::vec3(centroid * part, part);
                if (part > share[index]) share[index] = part, texelOut.sourceTriangle = t;
                glm::vec3 inside = glm::clamp(w, 0.0f, 1.0f);
                Atlas::SourcePart sourcePart{t, part * areaScale, inside / (inside.x + inside.y + inside.z)};
                sourcePart.corners = uint32_t(polygons.size()), sourcePart.cornerCount = uint32_t(polygon.size());
                for (const glm::vec2& corner : polygon) polygons.push_back(corner + offset);
                parts.push_back({index, sourcePart});
              }
            }
            glm::vec3 w;
            if (!barycentric2(q[0], q[1], q[2], glm::vec2(float(tx) + 0.5f, float(ty) + 0.5f), w)) continue;
            if (w.x < -1e-6f || w.y < -1e-6f || w.z < -1e-6f) continue;
            if (texelOut.kind != AtlasTexel::kEmpty) continue;
            texelOut.kind = core ? AtlasTexel::kCore : AtlasTexel::kBorder;
            texelOut.triangle = t;
            glm::vec3 clamped = glm::clamp(w, 0.0f, 1.0f);
            texelOut.barycentric = clamped / std::max(clamped.x + clamped.y + clamped.z, 1e-12f);
            texelOut.chart = int(ci);
          }
      }
      // The core triangle holding each square's centroid, if one does.
      std::unordered_map<uint32_t, size_t> placedIndex;
      for (size_t i = 0; i < chart.core.size(); ++i) placedIndex[chart.placed[i].first] = i;
      for (size_t i = 0; i < chart.core.size(); ++i) {
        const auto& [tri, q] = chart.placed[i];
        glm::ivec2 lo = glm::max(glm::ivec2(glm::floor(glm::min(q[0], glm::min(q[1], q[2])))), glm::ivec2(0));
        glm::ivec2 hi = glm::min(glm::ivec2(glm::ceil(glm::max(q[0], glm::max(q[1], q[2])))), rect.size - 1);
        for (int ty = lo.y; ty <= hi.y; ++ty)
          for (int tx = lo.x; tx <= hi.x; ++tx) {
            size_t index = size_t(rect.origin.y + ty) * size_t(atlas.width) + size_t(rect.origin.x + tx);
            if (holder[index] != AtlasTexel::kNone || !(moment[index].z > 0.0f)) continue;
            glm::vec3 w;
            glm::vec2 centroid = glm::vec2(moment[index]) / moment[index].z;
            if (barycentric2(q[0], q[1], q[2], centroid, w) && w.x >= -1e-6f && w.y >= -1e-6f && w.z >= -1e-6f)
              holder[index] = tri;
          }
      }
      // The source point: the centroid of the whole core part in the square, on the plane of the
      // triangle with most of it. A square with a part of the core and no centre on the surface
      // receives at that point.
      for (int ty = 0; ty < rect.size.y; ++ty)
        for (int tx = 0; tx < rect.size.x; ++tx) {
          size_t index = size_t(rect.origin.y + ty) * size_t(atlas.width) + size_t(rect.origin.x + tx);
          AtlasTexel& t = atlas.texels[index];
          if (t.area > 0.0f) {
            glm::vec2 centroid = glm::vec2(moment[index]) / moment[index].z;
            // On the plane of the triangle with most of the square (holder: the one holding the
            // centroid, when one does).
            glm::vec3 best(1.0f / 3.0f);
            uint32_t tri = holder[index] != AtlasTexel::kNone ? holder[index] : t.sourceTriangle;
            const std::array<glm::vec2, 3>& q = chart.placed[placedIndex.at(tri)].second;
            barycentric2(q[0], q[1], q[2], centroid, best);
            t.sourceTriangle = tri;
            best = glm::clamp(best, -0.5f, 1.5f);
            t.sourceBarycentric = best / (best.x + best.y + best.z);
          }
          if (t.kind == AtlasTexel::kEmpty && t.area > 0.0f)
            t.kind = AtlasTexel::kBorder, t.triangle = t.sourceTriangle, t.barycentric = t.sourceBarycentric;
        }
      // Gaps (a fan's wedge, past an open edge): the nearest filled neighbour's point, no area.
      for (int pass = 0; pass < border + 1; ++pass) {
        std::vector<std::pair<size_t, size_t>> fills;
        for (int ty = 0; ty < rect.size.y; ++ty)
          for (int tx = 0; tx < rect.size.x; ++tx) {
            size_t here = size_t(rect.origin.y + ty) * size_t(atlas.width) + size_t(rect.origin.x + tx);
            if (atlas.texels[here].kind != AtlasTexel::kEmpty) continue;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                int nx = tx + dx, ny = ty + dy;
                if (nx < 0 || ny < 0 || nx >= rect.size.x || ny >= rect.size.y) continue;
                size_t there = size_t(rect.origin.y + ny) * size_t(atlas.width) + size_t(rect.origin.x + nx);
                if (atlas.texels[there].kind != AtlasTexel::kEmpty) {
                  fills.emplace_back(here, there);
                  dx = dy = 2;  // the first found
                }
              }
          }
        if (fills.empty()) break;
        for (auto [here, there] : fills) {
          if (atlas.texels[here].kind != AtlasTexel::kEmpty) continue;
          AtlasTexel filler = atlas.texels[there];
          filler.kind = AtlasTexel::kBorder, filler.area = 0.0f;
          filler.sourceTriangle = AtlasTexel::kNone, filler.sourceBarycentric = glm::vec3(0.0f);
          atlas.texels[here] = filler;
        }
      }
    }
    // An island that covers a texel more than once folds or wraps over itself: charted again.
    bool overlapping = false;
    for (size_t ci = 0; ci < charts.size() && round == 0; ++ci) {
      if (charts[ci].island < 0) continue;
      const Atlas::Rect& rect = atlas.rects[ci];
      for (int ty = 0; ty < rect.size.y && !islands[size_t(charts[ci].island)].refused; ++ty)
        for (int tx = 0; tx < rect.size.x; ++tx)
          if (moment[size_t(rect.origin.y + ty) * size_t(atlas.width) + size_t(rect.origin.x + tx)].z > kMaxUvCover) {
            islands[size_t(charts[ci].island)].refused = true, overlapping = true;
            break;
          }
    }
    if (overlapping) continue;
    std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    atlas.partStart.assign(atlas.texels.size() + 1, 0);
    for (const auto& part : parts) ++atlas.partStart[part.first + 1];
    for (size_t i = 0; i < atlas.texels.size(); ++i) atlas.partStart[i + 1] += atlas.partStart[i];
    atlas.parts.reserve(parts.size());
    atlas.partCorners.reserve(polygons.size());
    for (auto& [index, part] : parts) {
      part.share /= atlas.texels[index].area;
      const uint32_t first = part.corners;
      part.corners = uint32_t(atlas.partCorners.size());
      atlas.partCorners.insert(atlas.partCorners.end(), polygons.begin() + first, polygons.begin() + first + part.cornerCount);
      atlas.parts.push_back(part);
    }
    return atlas;
  }
}

}  // namespace subsplat
