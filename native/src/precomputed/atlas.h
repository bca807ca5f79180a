// The texture atlas of one mesh for PRECOMPUTED (Lensch et al. 2002, Section 5.1;
// docs/PRECOMPUTED.md, "The atlas"):
//
//  0. With the mesh's UV map, each of its islands (cut at creases, kCreaseDegrees) that fits
//     (below, kMaxUvStretch) is a chart: its UVs scaled to world units. Steps 1 and 2 chart the rest.
//  1. Charts: starting from the first triangle not yet in one, a chart grows over shared edges
//     while each triangle's normal is within kMaxDeviationDegrees of the chart's mean normal.
//  2. Each chart is projected orthographically onto the plane of its mean normal, and turned so
//     that its bounding box has the least area.
//  3. Border: the triangles around the chart are unfolded into its plane across shared edges but
//     creases (each keeps its own shape; a fan around a vertex may leave a wedge), ring by ring, and fill the
//     texels around the chart's core out to `border` texels; a texel the unfolding leaves empty
//     takes its nearest filled neighbour's point with no area (a place for the display's bilinear
//     lookup, which adds no light).
//  4. The charts' rectangles (core plus border on every side) are packed on shelves.
//
// Every translucent triangle is the core of exactly one chart; a texel belongs to at most one chart.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace subsplat {

// A texel is two things (Lensch et al. 2002, Section 5.3): a receiver, the surface point at its
// centre (where the display's bilinear lookup reads it), and a source, the part of its chart's
// core inside its square (the piecewise constant basis: its area, and the point at its centroid,
// where its irradiance is sampled). A core texel's centre is on the core; a border texel's on an
// unfolded neighbour (or, in a gap, its nearest neighbour's point); either may hold a source part.
struct AtlasTexel {
  static constexpr uint32_t kNone = 0xffffffffu;
  enum Kind : uint8_t { kEmpty = 0, kCore = 1, kBorder = 2 };
  uint32_t triangle = kNone;    // the mesh triangle its centre's point lies on
  glm::vec3 barycentric{0.0f};  // of that point on the triangle
  float area = 0.0f;            // the core's surface area inside the square, world units^2
  uint32_t sourceTriangle = kNone;    // area > 0: the triangle with most of it
  glm::vec3 sourceBarycentric{0.0f};  // the centroid of that triangle's part
  int32_t chart = -1;
  uint8_t kind = kEmpty;
};

struct Atlas {
  int width = 0, height = 0;  // texels
  float texel = 0.0f;         // texel side, world units
  int border = 0;             // texels of border around each chart's core
  std::vector<AtlasTexel> texels;  // row by row
  int charts = 0;
  int uvCharts = 0;          // of them, islands of the mesh's UV map (the first uvCharts)
  int uvIslandsRefused = 0;  // islands charted as if there were no UV map (stretched, folded, overlapping)
  struct Rect {
    glm::ivec2 origin{0}, size{0};  // the chart's rectangle, border included
  };
  std::vector<Rect> rects;                // per chart
  std::vector<int32_t> chartOfTriangle;   // -1: not in the atlas (opaque, degenerate)
  std::vector<glm::vec2> cornerTexel;     // 3 per triangle: the corners in atlas texels (core)
  // A texel's source as the parts of the core triangles inside its square, by texel:
  // parts[partStart[i]] .. parts[partStart[i + 1]]. The hats' integrals over a part are its share
  // of the texel's area times the barycentric coordinates of its centroid (exact for linear hats);
  // its polygon (convex, in atlas texels) is what the near kernels integrate the profile over.
  struct SourcePart {
    uint32_t triangle = 0;
    float share = 0.0f;            // of the texel's area (world units), the parts' sum 1
    glm::vec3 barycentric{0.0f};   // of the part's centroid on its triangle
    uint32_t corners = 0, cornerCount = 0;  // partCorners[corners] .. [corners + cornerCount]
  };
  std::vector<uint32_t> partStart;
  std::vector<SourcePart> parts;
  std::vector<glm::vec2> partCorners;  // atlas texels
  const AtlasTexel& at(int x, int y) const { return texels[size_t(y) * size_t(width) + size_t(x)]; }
};

constexpr float kMaxDeviationDegrees = 30.0f;
// Two triangles whose normals differ by more than this meet at a crease, which the border does not
// unfold across (a cylinder's rim; a smooth surface's neighbours are a few degrees apart).
constexpr float kCreaseDegrees = 60.0f;

// The mesh's own UV map (docs/PRECOMPUTED.md, "The mesh's own UV map"): an island is a chart when
// each of its triangles, its UVs scaled by the island's ratio of world to UV area, is stretched by
// at most this factor along any direction and shrunk by at most its inverse (so a texel's extent on
// the surface stays within 1.5 of the texel chosen for the profile), when its triangles all have
// one winding, and when no texel's square holds more than kMaxUvCover of its core (of the square's
// area: the island wraps over itself). Not fitted to any scene.
constexpr float kMaxUvStretch = 1.5f;
constexpr float kMaxUvCover = 1.01f;

// The atlas of a mesh in world space (positions, 3 indices a triangle); `include` says which
// triangles are in it (translucent ones). Texel side `texel` (world units) and `border` texels.
// With `uvs` (one a vertex), the UV map's islands that fit are charts (step 0 above); the rest are
// charted as without. Throws Error(SS_LIMIT_EXCEEDED) past maxTexels texels.
Atlas buildAtlas(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices,
                 const std::vector<char>& include, float texel, int border, size_t maxTexels,
                 const std::vector<glm::vec2>* uvs = nullptr);

// Welds the corners that share a position: the index of each vertex's first copy.
std::vector<uint32_t> weldVertices(const std::vector<glm::vec3>& positions);

}  // namespace subsplat
