// PRECOMPUTED (issue 24; docs/PRECOMPUTED.md): the atlas, energy on a plane, a sphere against
// REFERENCE beside FULL, and what the precomputation is reused for.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "precomputed/atlas.h"
#include "precomputed/precomputed_transport.h"
#include "scene.h"
#include "util/error.h"
#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace subsplat {
namespace {

class Precomputed : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError(); }
  void TearDown() override { ssReleaseContext(context); }
  std::vector<float> render(int method, int size, SsStats* stats = nullptr, int resolution = 0,
                            uint32_t referenceSamples = 0) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.irradiance_resolution = resolution;
    settings.precomputed_atlas = atlas;
    settings.forward_shift = forwardShift;
    if (referenceSamples) settings.reference_samples = referenceSamples;
    EXPECT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    std::vector<float> rgba(size_t(size) * size * 4);
    EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
    SsStats s{};
    EXPECT_EQ(ssGetStats(context, &s), SS_OK);
    if (stats) *stats = s;
    return rgba;
  }
  testing::EglContext gl;
  SsContext context = nullptr;
  int atlas = SS_ATLAS_UV_MAP;  // render's settings.precomputed_atlas
  int forwardShift = SS_FORWARD_SHIFT_ON;  // render's settings.forward_shift
};

// A square of half-size `half` in z = 0 cut into n x n cells (two triangles each), normals up.
struct Grid {
  Grid(int n, float half) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        positions.insert(positions.end(), {-half + 2 * half * i / n, -half + 2 * half * j / n, 0.0f});
        normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
        indices.insert(indices.end(), {a, b, d, a, d, c});
      }
  }
  SsMeshDesc desc(uint32_t material) const {
    SsMeshDesc d{};
    d.positions = positions.data();
    d.normals = normals.data();
    d.vertex_count = uint32_t(positions.size() / 3);
    d.indices = indices.data();
    d.triangle_count = uint32_t(indices.size() / 3);
    d.default_material = material;
    for (int i = 0; i < 4; ++i) d.object_to_world[5 * i] = 1.0f;
    return d;
  }
  std::vector<float> positions, normals;
  std::vector<uint32_t> indices;
};

// The mean exitance over the middle of the frame (the exitance pass, rgb).
glm::dvec3 meanExitance(SsContext context, int size) {
  std::vector<float> pass(size_t(size) * size * 4);
  EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, size, size, pass.data()), SS_OK) << ssGetLastError();
  glm::dvec3 sum(0.0);
  int count = 0;
  for (int y = size / 4; y < 3 * size / 4; ++y)
    for (int x = size / 4; x < 3 * size / 4; ++x, ++count)
      for (int c = 0; c < 3; ++c) sum[c] += pass[(size_t(y) * size + x) * 4 + c];
  return sum / double(count);
}

// Energy: a large plane under a sun (its middle far from the edges) has the exitance of a lit
// half-space, E R_total, however the mesh is cut: PRECOMPUTED's against REFERENCE's. REFERENCE sums
// the same plane's light whatever its cells, so it renders once, from the uncut square.
TEST_F(Precomputed, PlaneConservesEnergy) {
  SsMaterialDesc material = testing::skinMaterial(10.0f);
  SsCameraDesc camera = testing::topDownCamera(0.5f);
  SsLightDesc sun = testing::sunLight(3.0f, 30.0f);
  ASSERT_EQ(ssSetMaterial(context, 0, &material), SS_OK);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  ASSERT_EQ(ssSetLights(context, &sun, 1), SS_OK);
  const int size = 32;
  glm::dvec3 truth(0.0);
  for (int cuts : {1, 16, 48}) {
    Grid grid(cuts, 2.0f);
    SsMeshDesc mesh = grid.desc(0);
    ASSERT_EQ(ssSetMesh(context, 0, &mesh), SS_OK);
    if (cuts == 1) {
      render(SS_METHOD_REFERENCE, size);
      truth = meanExitance(context, size);
    }
    SsStats stats{};
    render(SS_METHOD_PRECOMPUTED, size, &stats);
    glm::dvec3 ours = meanExitance(context, size);
    std::printf("%d cuts: texels %llu factors %llu; PRECOMPUTED / REFERENCE %.4f %.4f %.4f\n", cuts,
                (unsigned long long)stats.precomputed_texels, (unsigned long long)stats.precomputed_factors,
                ours.x / truth.x, ours.y / truth.y, ours.z / truth.z);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ours[c] / truth[c], 1.0, 0.01) << cuts << " cuts, channel " << c;
  }
}

// The atlas (Lensch et al. 2002, Section 5.1) of a UV sphere: every triangle the core of exactly
// one chart, covered where it has a texel centre; a texel in at most one chart's rectangle; each
// core texel's point where the display's atlas coordinates put it; a border of at least 3 texels
// around every core texel of a closed mesh.
TEST(PrecomputedAtlas, CoversEachTriangleOnceWithBorders) {
  testing::Sphere sphere;
  std::vector<glm::vec3> positions;
  for (size_t i = 0; i < sphere.positions.size(); i += 3)
    positions.emplace_back(sphere.positions[i], sphere.positions[i + 1], sphere.positions[i + 2]);
  const size_t triangles = sphere.indices.size() / 3;
  std::vector<char> include(triangles, 1);
  const int border = 4;
  Atlas atlas = buildAtlas(positions, sphere.indices, include, 0.02f, border, size_t(1) << 24);
  ASSERT_GT(atlas.charts, 1);
  // Each triangle with area is in one chart; rectangles do not overlap.
  for (size_t t = 0; t < triangles; ++t) {
    glm::vec3 a = positions[sphere.indices[3 * t]], b = positions[sphere.indices[3 * t + 1]], c = positions[sphere.indices[3 * t + 2]];
    if (glm::length(glm::cross(b - a, c - a)) > 0.0f) EXPECT_GE(atlas.chartOfTriangle[t], 0) << t;
  }
  std::vector<int> owner(atlas.texels.size(), -1);
  for (int c = 0; c < atlas.charts; ++c) {
    const Atlas::Rect& r = atlas.rects[size_t(c)];
    for (int y = r.origin.y; y < r.origin.y + r.size.y; ++y)
      for (int x = r.origin.x; x < r.origin.x + r.size.x; ++x) {
        int& o = owner[size_t(y) * size_t(atlas.width) + size_t(x)];
        EXPECT_EQ(o, -1) << "texel " << x << ", " << y << " in charts " << o << " and " << c;
        o = c;
      }
  }
  size_t core = 0, worst = 0;
  double far = 0.0;
  for (int y = 0; y < atlas.height; ++y)
    for (int x = 0; x < atlas.width; ++x) {
      const AtlasTexel& t = atlas.at(x, y);
      if (t.kind == AtlasTexel::kEmpty) continue;
      EXPECT_EQ(owner[size_t(y) * size_t(atlas.width) + size_t(x)], t.chart);
      if (t.kind != AtlasTexel::kCore) continue;
      ++core;
      EXPECT_EQ(atlas.chartOfTriangle[t.triangle], t.chart);
      // The display's coordinates of the triangle's corners put the texel's centre at its point.
      glm::vec2 q[3];
      glm::vec3 p[3];
      for (int k = 0; k < 3; ++k) q[k] = atlas.cornerTexel[3 * t.triangle + k], p[k] = positions[sphere.indices[3 * t.triangle + k]];
      glm::vec2 centre(x + 0.5f, y + 0.5f);
      float d = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
      float w1 = ((centre.x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (centre.y - q[0].y)) / d;
      float w2 = ((q[1].x - q[0].x) * (centre.y - q[0].y) - (centre.x - q[0].x) * (q[1].y - q[0].y)) / d;
      glm::vec3 shown = (1 - w1 - w2) * p[0] + w1 * p[1] + w2 * p[2];
      glm::vec3 held = t.barycentric.x * p[0] + t.barycentric.y * p[1] + t.barycentric.z * p[2];
      far = std::max(far, double(glm::length(shown - held)));
      // The border: every texel within `border` of a core texel holds a point.
      for (int dy = -border; dy <= border; ++dy)
        for (int dx = -border; dx <= border; ++dx) {
          int nx = x + dx, ny = y + dy;
          bool inside = nx >= 0 && ny >= 0 && nx < atlas.width && ny < atlas.height;
          if (!inside || atlas.at(nx, ny).kind == AtlasTexel::kEmpty) ++worst;
        }
    }
  double coreArea = 0.0, meshArea = 0.0;
  for (const AtlasTexel& t : atlas.texels)
    coreArea += t.area;
  for (size_t t = 0; t < triangles; ++t) {
    glm::vec3 a = positions[sphere.indices[3 * t]], b = positions[sphere.indices[3 * t + 1]], c = positions[sphere.indices[3 * t + 2]];
    meshArea += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  std::printf("core area %g, mesh area %g, %d charts, %d x %d\n", coreArea, meshArea, atlas.charts, atlas.width, atlas.height);
  EXPECT_NEAR(coreArea / meshArea, 1.0, 1e-3) << "the texels' core parts are the mesh's area";
  // Each texel's parts (its flux's hats, the near kernels' polygons): their shares sum to one, and
  // each part lies on its triangle, in the texel's square, with its own chart's triangle.
  ASSERT_EQ(atlas.partStart.size(), atlas.texels.size() + 1);
  double worstShare = 0.0;
  size_t misplaced = 0;
  for (size_t i = 0; i < atlas.texels.size(); ++i) {
    const AtlasTexel& t = atlas.texels[i];
    if (t.area <= 0.0f) {
      EXPECT_EQ(atlas.partStart[i + 1], atlas.partStart[i]);
      continue;
    }
    const glm::vec2 corner(float(i % size_t(atlas.width)), float(i / size_t(atlas.width)));
    double share = 0.0;
    for (uint32_t k = atlas.partStart[i]; k < atlas.partStart[i + 1]; ++k) {
      const Atlas::SourcePart& part = atlas.parts[k];
      share += part.share;
      if (std::abs(part.barycentric.x + part.barycentric.y + part.barycentric.z - 1.0f) > 1e-5f ||
          glm::any(glm::lessThan(part.barycentric, glm::vec3(0.0f))) || atlas.chartOfTriangle[part.triangle] != t.chart)
        ++misplaced;
      for (uint32_t c = 0; c < part.cornerCount; ++c) {
        glm::vec2 q = atlas.partCorners[part.corners + c] - corner;
        if (q.x < -1e-4f || q.y < -1e-4f || q.x > 1.0001f || q.y > 1.0001f) ++misplaced;
      }
    }
    worstShare = std::max(worstShare, std::abs(share - 1.0));
  }
  EXPECT_LT(worstShare, 1e-4) << "a texel's parts' shares do not sum to one";
  EXPECT_EQ(misplaced, 0u) << "parts off their triangle, their chart or their texel's square";
  EXPECT_GT(core, 1000u);
  EXPECT_LT(far, 1e-4) << "a core texel's point is " << far << " from where the display shows it";
  EXPECT_EQ(worst, 0u) << "texels within the border of a core texel hold no point";
}

// A cube's six faces meet at creases (90 degrees): no border texel of a face's chart receives on
// another face (the display's bilinear lookup would blend that face's exitance, a lit cap beside a
// dark side, into the face's last half texel: marble_pieces' cylinder rim, docs/PRECOMPUTED.md), and
// every texel within the border of a core texel still holds a point (its face's nearest).
TEST(PrecomputedAtlas, BordersDoNotCrossCreases) {
  const std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::vector<uint32_t> indices = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                         1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  const size_t triangles = indices.size() / 3;
  const int border = 4;
  Atlas atlas = buildAtlas(positions, indices, std::vector<char>(triangles, 1), 0.05f, border, size_t(1) << 24);
  ASSERT_EQ(atlas.charts, 6) << "a chart per face";
  auto normal = [&](uint32_t t) {
    glm::vec3 a = positions[indices[3 * t]], b = positions[indices[3 * t + 1]], c = positions[indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
  };
  std::vector<glm::vec3> chartNormal(6, glm::vec3(0.0f));
  for (uint32_t t = 0; t < triangles; ++t) chartNormal[size_t(atlas.chartOfTriangle[t])] = normal(t);
  size_t border_texels = 0, across = 0, missing = 0;
  for (int y = 0; y < atlas.height; ++y)
    for (int x = 0; x < atlas.width; ++x) {
      const AtlasTexel& t = atlas.at(x, y);
      if (t.kind == AtlasTexel::kBorder) {
        ++border_texels;
        if (glm::dot(normal(t.triangle), chartNormal[size_t(t.chart)]) < 0.99f) ++across;
      }
      if (t.kind != AtlasTexel::kCore) continue;
      for (int dy = -border; dy <= border; ++dy)
        for (int dx = -border; dx <= border; ++dx) {
          int nx = x + dx, ny = y + dy;
          bool inside = nx >= 0 && ny >= 0 && nx < atlas.width && ny < atlas.height;
          if (!inside || atlas.at(nx, ny).kind == AtlasTexel::kEmpty) ++missing;
        }
    }
  EXPECT_GT(border_texels, 6u * 4u * 20u);
  EXPECT_EQ(across, 0u) << "border texels receive on another face";
  EXPECT_EQ(missing, 0u) << "texels within the border of a core texel hold no point";
}

// A unit cube with 4 x 4 cells a face and a UV map unfolded as a cross: the four sides in a row
// (u 0..4), the top above the front and the bottom below it. Isometric, one winding; its faces
// meet at creases.
struct CrossCube {
  explicit CrossCube(int n = 4) {
    struct Face {
      glm::vec3 origin, u, v;
      glm::vec2 uv;
    };
    const Face faces[6] = {{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0}},  {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0}},
                           {{1, 1, 0}, {-1, 0, 0}, {0, 0, 1}, {2, 0}}, {{0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {3, 0}},
                           {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 1}},  {{0, 1, 0}, {1, 0, 0}, {0, -1, 0}, {0, -1}}};
    for (const Face& f : faces) {
      const uint32_t first = uint32_t(positions.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          const float s = float(i) / float(n), t = float(j) / float(n);
          positions.push_back(f.origin + s * f.u + t * f.v);
          uvs.push_back(f.uv + glm::vec2(s, t));
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          uint32_t a = first + uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
          indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    }
  }
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;
};

// A closed cylinder of radius 1 and height 2 (z from -1 to 1), `segments` around and `rows` up its
// side, with Blender's UV map: the side unrolled (u the arc length from a seam, v the height;
// isometric), each cap a disc.
struct UvCylinder {
  explicit UvCylinder(int segments = 32, int rows = 8) {
    for (int j = 0; j <= rows; ++j)
      for (int i = 0; i <= segments; ++i) {
        const float a = 2.0f * float(M_PI) * float(i) / float(segments), z = -1.0f + 2.0f * float(j) / float(rows);
        positions.emplace_back(std::cos(a), std::sin(a), z), normals.emplace_back(std::cos(a), std::sin(a), 0.0f);
        uvs.emplace_back(a, z);
      }
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < segments; ++i) {
        uint32_t p = uint32_t(j * (segments + 1) + i), q = p + 1, r = p + uint32_t(segments + 1), t = r + 1;
        indices.insert(indices.end(), {p, q, t, p, t, r});
      }
    for (float side : {-1.0f, 1.0f}) {
      const uint32_t centre = uint32_t(positions.size());
      positions.emplace_back(0.0f, 0.0f, side), normals.emplace_back(0.0f, 0.0f, side), uvs.emplace_back(0.0f, 0.0f);
      for (int i = 0; i < segments; ++i) {
        const float a = 2.0f * float(M_PI) * float(i) / float(segments);
        positions.emplace_back(std::cos(a), std::sin(a), side), normals.emplace_back(0.0f, 0.0f, side);
        uvs.emplace_back(std::cos(a), std::sin(a));
      }
      for (int i = 0; i < segments; ++i) {
        uint32_t p = centre + 1 + uint32_t(i), q = centre + 1 + uint32_t((i + 1) % segments);
        if (side > 0.0f) indices.insert(indices.end(), {centre, p, q});
        else indices.insert(indices.end(), {centre, q, p});
      }
    }
  }
  // Turned to show its side and top cap to a camera looking down -z.
  SsMeshDesc desc(float radius, uint32_t material, bool withUvs) const {
    SsMeshDesc d{};
    d.positions = &positions[0].x;
    d.normals = &normals[0].x;
    d.uvs = withUvs ? &uvs[0].x : nullptr;
    d.vertex_count = uint32_t(positions.size());
    d.indices = indices.data();
    d.triangle_count = uint32_t(indices.size() / 3);
    d.default_material = material;
    const glm::mat4 m = glm::rotate(glm::mat4(1.0f), glm::radians(-50.0f), glm::vec3(1, 0, 0)) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(radius));
    std::memcpy(d.object_to_world, &m[0][0], sizeof d.object_to_world);
    return d;
  }
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;
};

// The mesh's own UV map (docs/PRECOMPUTED.md, "The mesh's own UV map"): an island that fits is one
// chart, laid out as the UVs are (every triangle covered, its core area the mesh's, each texel's
// point where the display's coordinates put it, a border around every core texel); an island
// that crosses a crease is cut there; an island stretched more than kMaxUvStretch, one that folds
// (two windings) and one that wraps over itself (a strip whose UVs turn through 2.5 turns) are each
// charted as without UVs.
TEST(PrecomputedAtlas, TakesTheUvMapsIslandsWhenTheyFit) {
  const int border = 3;
  UvCylinder cylinder;
  const std::vector<char> all(cylinder.indices.size() / 3, 1);
  Atlas own = buildAtlas(cylinder.positions, cylinder.indices, all, 0.02f, border, size_t(1) << 24, &cylinder.uvs);
  Atlas made = buildAtlas(cylinder.positions, cylinder.indices, all, 0.02f, border, size_t(1) << 24);
  std::printf("cylinder: %d charts from its UV map, %d x %d texels; without: %d charts, %d x %d\n", own.charts,
              own.width, own.height, made.charts, made.width, made.height);
  EXPECT_EQ(own.charts, 3) << "the side and the two caps";
  EXPECT_EQ(own.uvCharts, 3);
  EXPECT_EQ(own.uvIslandsRefused, 0);
  EXPECT_GT(made.charts, 3);
  double coreArea = 0.0, meshArea = 0.0;
  for (const AtlasTexel& t : own.texels) coreArea += t.area;
  for (size_t t = 0; t < all.size(); ++t) {
    const glm::vec3 a = cylinder.positions[cylinder.indices[3 * t]], b = cylinder.positions[cylinder.indices[3 * t + 1]],
                    c = cylinder.positions[cylinder.indices[3 * t + 2]];
    meshArea += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  EXPECT_NEAR(coreArea / meshArea, 1.0, 1e-3) << "the texels' core parts are the mesh's area";
  // Laid out as the UVs: within each chart the corners are the UVs scaled alike (the island's ratio
  // of world to UV area), turned and moved: every edge's length over its UV length the same.
  std::vector<glm::dvec2> ratios(size_t(own.charts), glm::dvec2(INFINITY, 0.0));  // least, most
  for (size_t t = 0; t < all.size(); ++t) {
    ASSERT_GE(own.chartOfTriangle[t], 0) << t;
    glm::dvec2& r = ratios[size_t(own.chartOfTriangle[t])];
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 a = own.cornerTexel[3 * t + size_t(k)], b = own.cornerTexel[3 * t + size_t((k + 1) % 3)];
      const glm::vec2 ua = cylinder.uvs[cylinder.indices[3 * t + size_t(k)]],
                      ub = cylinder.uvs[cylinder.indices[3 * t + size_t((k + 1) % 3)]];
      const double ratio = double(glm::length(b - a)) / double(glm::length(ub - ua));
      r = glm::dvec2(std::min(r.x, ratio), std::max(r.y, ratio));
    }
  }
  for (const glm::dvec2& r : ratios) EXPECT_LT(r.y / r.x - 1.0, 1e-3) << "a chart is not its island's shape";
  size_t far = 0, missing = 0, core = 0;
  for (int y = 0; y < own.height; ++y)
    for (int x = 0; x < own.width; ++x) {
      const AtlasTexel& t = own.at(x, y);
      if (t.kind != AtlasTexel::kCore) continue;
      ++core;
      glm::vec2 q[3];
      glm::vec3 p[3];
      for (int k = 0; k < 3; ++k)
        q[k] = own.cornerTexel[3 * t.triangle + k], p[k] = cylinder.positions[cylinder.indices[3 * t.triangle + k]];
      const glm::vec2 centre(x + 0.5f, y + 0.5f);
      const float d = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
      const float w1 = ((centre.x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (centre.y - q[0].y)) / d;
      const float w2 = ((q[1].x - q[0].x) * (centre.y - q[0].y) - (centre.x - q[0].x) * (q[1].y - q[0].y)) / d;
      const glm::vec3 shown = (1 - w1 - w2) * p[0] + w1 * p[1] + w2 * p[2];
      const glm::vec3 held = t.barycentric.x * p[0] + t.barycentric.y * p[1] + t.barycentric.z * p[2];
      if (glm::length(shown - held) > 1e-4f) ++far;
      for (int dy = -border; dy <= border; ++dy)
        for (int dx = -border; dx <= border; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= own.width || ny >= own.height || own.at(nx, ny).kind == AtlasTexel::kEmpty) ++missing;
        }
    }
  EXPECT_GT(core, 20000u);
  EXPECT_EQ(far, 0u) << "core texels' points away from where the display shows them";
  EXPECT_EQ(missing, 0u) << "texels within the border of a core texel hold no point";

  // The cross cube's one island is cut at its creases: a chart a face, each from the UV map.
  CrossCube cube;
  const std::vector<char> faces(cube.indices.size() / 3, 1);
  Atlas cut = buildAtlas(cube.positions, cube.indices, faces, 0.05f, border, size_t(1) << 24, &cube.uvs);
  EXPECT_EQ(cut.charts, 6);
  EXPECT_EQ(cut.uvCharts, 6);
  // Stretched: u three times v (sqrt 3 either way of each island's mean).
  std::vector<glm::vec2> stretched = cube.uvs;
  for (glm::vec2& uv : stretched) uv.x *= 3.0f;
  Atlas refused = buildAtlas(cube.positions, cube.indices, faces, 0.05f, border, size_t(1) << 24, &stretched);
  EXPECT_EQ(refused.uvCharts, 0);
  EXPECT_EQ(refused.uvIslandsRefused, 6);
  EXPECT_EQ(refused.charts, 6) << "charted as without UVs";

  // A flat strip (0.1 wide, 2.5 turns of a circle of radius 1 long) whose UVs wind it around that
  // circle: stretched by at most 1.1, one winding, and over itself after a turn.
  std::vector<glm::vec3> strip;
  std::vector<glm::vec2> polar;
  std::vector<uint32_t> stripIndices;
  const int segments = 400;
  const float length = 2.5f * 2.0f * float(M_PI);
  for (int i = 0; i <= segments; ++i)
    for (int j = 0; j < 2; ++j) {
      const float x = length * float(i) / float(segments), y = 0.1f * float(j), r = 1.0f + y;
      strip.emplace_back(x, y, 0.0f);
      polar.emplace_back(r * std::cos(x), r * std::sin(x));
    }
  for (uint32_t i = 0; i < uint32_t(segments); ++i)
    stripIndices.insert(stripIndices.end(), {2 * i, 2 * i + 2, 2 * i + 3, 2 * i, 2 * i + 3, 2 * i + 1});
  const std::vector<char> strips(stripIndices.size() / 3, 1);
  Atlas wrapped = buildAtlas(strip, stripIndices, strips, 0.02f, border, size_t(1) << 24, &polar);
  Atlas plain = buildAtlas(strip, stripIndices, strips, 0.02f, border, size_t(1) << 24);
  EXPECT_EQ(wrapped.uvCharts, 0);
  EXPECT_EQ(wrapped.uvIslandsRefused, 1);
  EXPECT_EQ(wrapped.charts, plain.charts);
  EXPECT_EQ(wrapped.width * wrapped.height, plain.width * plain.height);
  // A third of it (under one turn) fits; folded back on itself half way, it does not.
  std::vector<uint32_t> third(stripIndices.begin(), stripIndices.begin() + ptrdiff_t(stripIndices.size() / 3));
  const std::vector<char> thirds(third.size() / 3, 1);
  Atlas turn = buildAtlas(strip, third, thirds, 0.02f, border, size_t(1) << 24, &polar);
  EXPECT_EQ(turn.uvCharts, 1);
  EXPECT_EQ(turn.uvIslandsRefused, 0);
  std::vector<glm::vec2> folded = polar;
  const float half = 0.5f * length / 3.0f;
  for (size_t i = 0; i < strip.size(); ++i)
    if (strip[i].x > half) {
      const float x = 2.0f * half - strip[i].x, r = 1.0f + strip[i].y;
      folded[i] = glm::vec2(r * std::cos(x), r * std::sin(x));
    }
  Atlas fold = buildAtlas(strip, third, thirds, 0.02f, border, size_t(1) << 24, &folded);
  EXPECT_EQ(fold.uvCharts, 0);
  EXPECT_EQ(fold.uvIslandsRefused, 1);
}

// The UV cylinder (turned to show its side and top) under the lit sphere's lights, its atlas made
// (SS_ATLAS_MADE) and then from its UV map (the default; a change of the setting precomputes
// again): from its UV map, the atlas is its three islands, and its image against REFERENCE (100 000
// samples) as near as the made atlas's (within 0.3 points) and no further than FULL's.
TEST_F(Precomputed, TheUvMapsAtlasIsAsNearToReference) {
  UvCylinder cylinder;
  testing::Sphere unused;
  SsMaterialDesc material = testing::skinMaterial(30.0f);
  ASSERT_EQ(testing::setLitSphere(context, unused, material), SS_OK) << ssGetLastError();
  SsMeshDesc desc = cylinder.desc(0.2f, 0, true);
  ASSERT_EQ(ssSetMesh(context, 0, &desc), SS_OK) << ssGetLastError();
  const int size = 48;
  double errors[2] = {0.0, 0.0}, fullError = 0.0;
  std::vector<float> truth;
  for (int own = 0; own < 2; ++own) {
    atlas = own ? SS_ATLAS_UV_MAP : SS_ATLAS_MADE;
    SsStats stats{};
    std::vector<float> ours = render(SS_METHOD_PRECOMPUTED, size, &stats);
    EXPECT_EQ(stats.transport_reused, 0) << "the atlas setting changed";
    SsPrecomputedObject object{};
    uint32_t count = 0;
    ASSERT_EQ(ssGetPrecomputedObjects(context, &object, 1, &count), SS_OK);
    ASSERT_EQ(count, 1u);
    EXPECT_EQ(object.uv_charts, own ? 3 : 0) << "the UV map's islands are the atlas";
    if (own) EXPECT_EQ(object.charts, 3);
    if (truth.empty()) truth = render(SS_METHOD_REFERENCE, size, nullptr, 0, 100000);
    errors[own] = testing::relativeRmse(ours, truth);
    if (own) {
      fullError = testing::relativeRmse(render(SS_METHOD_FULL, size), truth);
      EXPECT_LE(errors[1], fullError) << testing::writeComparison("precomputed_uv_cylinder", ours, truth, size, size);
    }
    std::printf("%s: %d charts, %llu texels, %.1f MiB; against REFERENCE %.4f\n", own ? "its UV map" : "made",
                object.charts, (unsigned long long)object.texels, double(object.bytes) / 1048576.0, errors[own]);
  }
  std::printf("FULL against REFERENCE %.4f\n", fullError);
  EXPECT_LT(errors[1], errors[0] + 0.003);
}

// The lit sphere (a sun at 70 degrees and a point light behind: a terminator, curvature, a thin
// rim) against REFERENCE (at 100 000 samples; 48 x 48 pixels), under each profile model, and under
// TABULATED with and without its forward shift (PRECOMPUTED moves the illumination map's flux):
// within 1.5 % and no further than FULL's image (measured 0.37 % against FULL's 1.04 % with DIPOLE;
// TABULATED 0.48 % against 1.31 % without the shift, 1.45 % against 1.80 % with it), and the frame
// that reuses the precomputation is the one that made it. Times are printed, not asserted.
TEST_F(Precomputed, LitSphereAgainstReference) {
  testing::Sphere sphere;
  const std::pair<int, int> cases[] = {{SS_PROFILE_DIPOLE, SS_FORWARD_SHIFT_ON},
                                       {SS_PROFILE_TABULATED, SS_FORWARD_SHIFT_OFF},
                                       {SS_PROFILE_TABULATED, SS_FORWARD_SHIFT_ON}};
  for (auto [model, shift] : cases) {
    SCOPED_TRACE(model == SS_PROFILE_DIPOLE ? "DIPOLE" : shift == SS_FORWARD_SHIFT_ON ? "TABULATED" : "TABULATED, no shift");
    forwardShift = shift;
    SsMaterialDesc material = testing::skinMaterial(30.0f);
    material.profile_model = model;
    ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
    const int size = 48;
    SsStats precomputation{}, relit{}, full{};
    std::vector<float> first = render(SS_METHOD_PRECOMPUTED, size, &precomputation);
    std::vector<float> again = render(SS_METHOD_PRECOMPUTED, size, &relit);
    std::vector<float> fullImage = render(SS_METHOD_FULL, size, &full);
    std::vector<float> truth = render(SS_METHOD_REFERENCE, size, nullptr, 0, 100000);
    double ours = testing::relativeRmse(again, truth), theirs = testing::relativeRmse(fullImage, truth);
    std::printf("precomputation %.0f ms (%llu bytes, %llu texels, %llu factors); relit frame %.1f ms (relight %.1f); "
                "FULL %.1f ms; against REFERENCE: PRECOMPUTED %.4f, FULL %.4f\n",
                precomputation.precompute_ms, (unsigned long long)relit.precomputed_bytes,
                (unsigned long long)relit.precomputed_texels, (unsigned long long)relit.precomputed_factors, relit.frame_ms,
                relit.relight_ms, full.frame_ms, ours, theirs);
    // The shift is applied as the map is lit: turning it on reuses the precomputation without it.
    EXPECT_EQ(precomputation.transport_reused, model == SS_PROFILE_TABULATED && shift == SS_FORWARD_SHIFT_ON ? 1 : 0);
    EXPECT_EQ(relit.transport_reused, 1);
    EXPECT_EQ(relit.precompute_ms, 0.0);
    EXPECT_EQ(first, again) << "two frames of one precomputation differ";
    EXPECT_LT(ours, 0.015) << testing::writeComparison("precomputed_sphere", again, truth, size, size);
    EXPECT_LE(ours, theirs) << testing::writeComparison("precomputed_sphere", again, truth, size, size);
  }
}

// What the precomputation serves: a light or camera move, and a rigid move of the object (turned
// and moved), relight it; a vertex moved, the object scaled or a material change precomputes again.
// Each frame is the same frame rendered by a context that precomputed for it (to the bit; after a
// rigid move, whose atlas a fresh precomputation cuts from positions that differ in their last
// bits, as close to REFERENCE within 0.3 points), and differs from the frame before (no stale image).
TEST_F(Precomputed, ReusedForLightsAndCameraNotForMeshOrMaterial) {
  testing::Sphere sphere(24, 12);
  SsMaterialDesc material = testing::skinMaterial(30.0f);
  ASSERT_EQ(testing::setLitSphere(context, sphere, material), SS_OK) << ssGetLastError();
  const int size = 32;
  SsStats stats{};
  render(SS_METHOD_PRECOMPUTED, size, &stats);
  EXPECT_EQ(stats.transport_reused, 0);
  EXPECT_GT(stats.precompute_ms, 0.0);
  EXPECT_GT(stats.precomputed_bytes, 0u);
  // The same frame from a context that precomputes it.
  auto fresh = [&](const std::function<void(SsContext)>& change) {
    SsContext other = nullptr;
    EXPECT_EQ(ssNewContext(&other), SS_OK);
    EXPECT_EQ(testing::setLitSphere(other, sphere, material), SS_OK);
    change(other);
    SsSettings settings = ssDefaultSettings();
    settings.method = SS_METHOD_PRECOMPUTED;
    EXPECT_EQ(ssSetSettings(other, &settings), SS_OK);
    std::vector<float> rgba(size_t(size) * size * 4);
    EXPECT_EQ(ssRender(other, size, size, rgba.data()), SS_OK) << ssGetLastError();
    SsStats s{};
    ssGetStats(other, &s);
    EXPECT_EQ(s.transport_reused, 0);
    ssReleaseContext(other);
    return rgba;
  };
  // exact: the frame equals a fresh precomputation's to the bit.
  struct Change {
    const char* what;
    bool reuses;
    std::function<void(SsContext)> apply;
    bool exact = true;
  };
  std::vector<float> positions = sphere.positions;
  positions[3 * 100 + 2] += 0.01f;  // one vertex
  auto dentedAt = [&](glm::mat4 toWorld) {
    SsMeshDesc d = sphere.desc(glm::vec3(0.0f), 0.3f, 0);
    d.positions = positions.data();
    std::memcpy(d.object_to_world, &toWorld[0][0], sizeof d.object_to_world);
    return d;
  };
  const glm::mat4 shift = glm::translate(glm::mat4(1.0f), glm::vec3(0.02f, 0.0f, 0.0f));
  const glm::mat4 turn = glm::rotate(shift, glm::radians(40.0f), glm::vec3(0.3f, 0.2f, 1.0f));
  SsMeshDesc dented = dentedAt(glm::scale(glm::mat4(1.0f), glm::vec3(0.3f)));
  SsMeshDesc shifted = dentedAt(glm::scale(shift, glm::vec3(0.3f)));
  SsMeshDesc turned = dentedAt(glm::scale(turn, glm::vec3(0.3f)));
  SsMeshDesc scaled = dentedAt(glm::scale(turn, glm::vec3(0.33f)));
  SsMaterialDesc other = material;
  other.sigma_a[0] *= 2.0f;
  const std::vector<Change> changes = {
      {"a light moved", true,
       [](SsContext c) {
         SsLightDesc lights[1] = {testing::sunLight(3.0f, 40.0f)};
         ssSetLights(c, lights, 1);
       }},
      {"the camera moved", true,
       [](SsContext c) {
         SsCameraDesc camera = testing::topDownCamera(0.4f);
         ssSetCamera(c, &camera);
       }},
      {"one vertex moved", false, [&](SsContext c) { ssSetMesh(c, 0, &dented); }},
      {"the object moved", true, [&](SsContext c) { ssSetMesh(c, 0, &shifted); }, false},
      {"the object turned", true, [&](SsContext c) { ssSetMesh(c, 0, &turned); }, false},
      {"the object scaled", false, [&](SsContext c) { ssSetMesh(c, 0, &scaled); }},
      {"the material changed", false, [&](SsContext c) { ssSetMaterial(c, 0, &other); }},
      {"the same mesh sent again", true, [&](SsContext c) { ssSetMesh(c, 0, &scaled); }},
  };
  std::function<void(SsContext)> all = [](SsContext) {};
  std::vector<float> last = render(SS_METHOD_PRECOMPUTED, size);
  for (const Change& change : changes) {
    change.apply(context);
    std::vector<float> image = render(SS_METHOD_PRECOMPUTED, size, &stats);
    EXPECT_EQ(stats.transport_reused, change.reuses ? 1 : 0) << change.what;
    EXPECT_EQ(stats.precompute_ms > 0.0, !change.reuses) << change.what;
    auto before = all;
    all = [before, apply = change.apply](SsContext c) { before(c), apply(c); };
    std::vector<float> truth = fresh(all);
    if (change.exact) {
      EXPECT_EQ(image, truth) << change.what << ": not the image of a fresh precomputation";
    } else {  // as close to REFERENCE as the fresh precomputation's frame (both against the same
              // REFERENCE image, whose noise at a quarter of its default samples moves both alike)
      std::vector<float> reference = render(SS_METHOD_REFERENCE, size, nullptr, 0, 50000);
      double ours = testing::relativeRmse(image, reference), theirs = testing::relativeRmse(truth, reference);
      std::printf("%s: against REFERENCE, relit %.4f, precomputed afresh %.4f (from each other %.4f)\n", change.what,
                  ours, theirs, testing::relativeRmse(image, truth));
      EXPECT_LE(ours, theirs + 0.003) << change.what;
    }
    if (std::string(change.what) != "the same mesh sent again")
      EXPECT_NE(image, last) << change.what << ": the frame did not change (a stale image)";
    last = image;
  }
}

// A frame's light views are their shadow maps alone where no material is TABULATED
// (docs/PRECOMPUTED.md, "A frame"): what they give the direct light must be what FULL's whole views
// give it. A grey floor reads the direct light and nothing of the exitance: under each kind of
// light, with the shadow map at the irradiance buffer's resolution and at its own, in one sample
// and in anti-aliasing's several (which keep copies of the maps), it is FULL's to the bit, the
// translucent sphere's shadow on it included.
TEST_F(Precomputed, ShadowsAreFullsUnderEveryLight) {
  testing::Quad quad;
  testing::Sphere sphere(24, 12);
  SsMaterialDesc grey = testing::greyMaterial(0.5f), skin = testing::skinMaterial(30.0f);
  SsMeshDesc floor = quad.desc(1.0f, 0), ball = sphere.desc(glm::vec3(0.0f, 0.0f, 0.3f), 0.3f, 1);
  SsCameraDesc camera = testing::topDownCamera(1.0f);
  ASSERT_EQ(ssSetMaterial(context, 0, &grey), SS_OK);
  ASSERT_EQ(ssSetMaterial(context, 1, &skin), SS_OK);
  ASSERT_EQ(ssSetMesh(context, 0, &floor), SS_OK);
  ASSERT_EQ(ssSetMesh(context, 1, &ball), SS_OK);
  ASSERT_EQ(ssSetCamera(context, &camera), SS_OK);
  auto towards = [](SsLightDesc& light, glm::vec3 from) {
    glm::vec3 d = glm::normalize(-from);
    for (int i = 0; i < 3; ++i) light.position[i] = from[i], light.direction[i] = d[i];
  };
  SsLightDesc softSun = testing::sunLight(3.0f, 45.0f), hardSun = softSun, point{}, spot{}, area{};
  softSun.soft_size = float(10.0 * M_PI / 180.0);
  point.type = SS_LIGHT_POINT, point.strength = 40.0f, point.soft_size = 0.1f;
  towards(point, glm::vec3(-0.6f, 0.0f, 1.2f));
  spot.type = SS_LIGHT_SPOT, spot.strength = 40.0f, spot.spot_size = 1.2f, spot.spot_blend = 0.2f;
  towards(spot, glm::vec3(0.6f, 0.3f, 1.2f));
  area.type = SS_LIGHT_AREA, area.strength = 40.0f, area.area_shape = SS_AREA_SQUARE, area.area_size[0] = 0.4f;
  area.area_axis[0] = 1.0f;
  towards(area, glm::vec3(0.0f, -0.6f, 1.2f));
  for (SsLightDesc* light : {&point, &spot, &area}) light->color[0] = light->color[1] = light->color[2] = 1.0f;
  const struct {
    const char* what;
    SsLightDesc light;
  } lights[] = {{"a sun with a disk", softSun}, {"a sun", hardSun}, {"a point light with a radius", point},
                {"a spot light", spot}, {"an area light", area}};
  const int size = 64;
  for (const auto& [what, light] : lights) {
    ASSERT_EQ(ssSetLights(context, &light, 1), SS_OK) << ssGetLastError();
    for (int shadowResolution : {128, 512})  // the irradiance buffer's, and a map of its own
    for (int samples : {1, 3}) {
      auto frame = [&](int method, std::vector<float>* exitance) {
        SsSettings settings = ssDefaultSettings();
        settings.method = method;
        settings.samples = samples;
        settings.irradiance_resolution = 128;
        settings.shadow_resolution = shadowResolution;
        EXPECT_EQ(ssSetSettings(context, &settings), SS_OK);
        std::vector<float> rgba(size_t(size) * size * 4);
        EXPECT_EQ(ssRender(context, size, size, rgba.data()), SS_OK) << ssGetLastError();
        if (exitance) {
          exitance->resize(rgba.size());
          EXPECT_EQ(ssGetPass(context, SS_PASS_EXITANCE, size, size, exitance->data()), SS_OK);
        }
        return rgba;
      };
      std::vector<float> exitance;
      std::vector<float> full = frame(SS_METHOD_FULL, nullptr), ours = frame(SS_METHOD_PRECOMPUTED, &exitance);
      int floorPixels = 0, different = 0;
      float darkest = 1e30f, brightest = 0.0f;
      auto sphereNear = [&](int x, int y) {  // anti-aliasing's other samples may see the sphere here
        for (int v = std::max(y - 1, 0); v <= std::min(y + 1, size - 1); ++v)
          for (int u = std::max(x - 1, 0); u <= std::min(x + 1, size - 1); ++u)
            if (exitance[4 * (size_t(v) * size + u) + 3] > 0.5f) return true;
        return false;
      };
      for (size_t i = 0; i < size_t(size) * size; ++i) {
        if (sphereNear(int(i % size), int(i / size))) continue;
        ++floorPixels;
        darkest = std::min(darkest, full[4 * i + 1]), brightest = std::max(brightest, full[4 * i + 1]);
        if (std::memcmp(&full[4 * i], &ours[4 * i], 3 * sizeof(float)) != 0) ++different;
      }
      EXPECT_GT(floorPixels, size * size / 2) << what;
      EXPECT_GT(brightest, 0.0f) << what << ": the floor is not lit";
      EXPECT_LT(darkest, 0.5f * brightest) << what << ": no shadow on the floor";
      EXPECT_EQ(different, 0) << what << ", shadow map " << shadowResolution << ", " << samples
                              << " samples: floor pixels unlike FULL's";
    }
  }
}

// The response of an object to a unit irradiance everywhere, per active texel (the local branch's
// kernels plus the global branch at its point): what relight computes with every texel's flux its
// area.
std::vector<glm::vec3> uniformResponse(const PrecomputedTransport::Object& o) {
  const Atlas& atlas = o.atlas;
  const size_t active = o.active.size();
  std::vector<glm::vec3> share(size_t(o.vertices), glm::vec3(0.0f)), vertex(size_t(o.vertices), glm::vec3(0.0f));
  for (size_t a = 0; a < active; ++a)
    for (uint32_t e = o.sourceStart[a]; e < o.sourceStart[a + 1]; ++e) {
      share[o.sourceVertex[e]] += o.sourceBeta[e] * atlas.texels[o.active[a]].area;
      vertex[o.sourceVertex[e]] += o.direct[e] * atlas.texels[o.active[a]].area;
    }
  for (size_t j = 0; j < size_t(o.vertices); ++j)
    for (uint32_t k = o.rowStart[j]; k < o.rowStart[j + 1]; ++k) vertex[j] += o.factor[k] * share[o.column[k]];
  std::vector<glm::vec3> response(active, glm::vec3(0.0f));
  for (size_t a = 0; a < active; ++a) {
    for (uint32_t k = o.kernelStart[a]; k < o.kernelStart[a + 1]; ++k)
      response[a] += o.kernelWeight[k] * atlas.texels[o.active[o.kernelSource[k]]].area;
    const AtlasTexel& t = atlas.texels[o.active[a]];
    for (int c = 0; c < 3; ++c) response[a] += t.barycentric[c] * vertex[o.vertexOfCorner[3 * size_t(t.triangle) + size_t(c)]];
  }
  return response;
}

// A chart's edge responds as the surface around it (docs/PRECOMPUTED.md, "What it is"): under a
// unit irradiance everywhere, on a sphere whose profile is shorter than a texel (the own texel's
// part is most of the response), each core texel's response against the mean of the core texels
// within 1.5 texels of it in 3D. A texel cut by a chart's edge carries a part that is not the
// square of its area: integrated as that square (before stop 49) such texels were 1.84 % from
// their neighbours (RMS; whole texels 0.34 %), over each part's own polygon 0.18 % (0.09 %).
TEST(PrecomputedKernels, AChartsEdgeRespondsAsItsNeighbours) {
  testing::Sphere sphere(24, 12);
  Scene scene;
  scene.setMaterial(0, testing::skinMaterial(50.0f));
  scene.setMesh(0, sphere.desc(glm::vec3(0.0f), 1.0f, 0));  // 5 cm
  scene.resolveMaterials();
  PrecomputedTransport transport;
  transport.precompute(scene, PrecomputedTransport::kDefaultBytes, {});
  ASSERT_EQ(transport.objects().size(), 1u);
  const PrecomputedTransport::Object& o = transport.objects()[0];
  const Atlas& atlas = o.atlas;
  const std::vector<glm::vec3> response = uniformResponse(o);
  std::vector<glm::vec3> position(o.active.size());
  std::vector<size_t> core;
  for (size_t a = 0; a < o.active.size(); ++a) {
    const AtlasTexel& t = atlas.texels[o.active[a]];
    for (int c = 0; c < 3; ++c) position[a] += t.barycentric[c] * o.vertexPositions[o.vertexOfCorner[3 * size_t(t.triangle) + size_t(c)]];
    if (t.kind == AtlasTexel::kCore) core.push_back(a);
  }
  const float near = 1.5f * atlas.texel, whole = 0.95f * atlas.texel * atlas.texel;
  std::map<std::tuple<int, int, int>, std::vector<size_t>> cells;  // of side `near`
  auto cellOf = [&](const glm::vec3& p) {
    glm::ivec3 c(glm::floor(p / near));
    return std::make_tuple(c.x, c.y, c.z);
  };
  for (size_t a : core) cells[cellOf(position[a])].push_back(a);
  double sum[2] = {0.0, 0.0};
  int count[2] = {0, 0};
  for (size_t a : core) {
    glm::vec3 mean(0.0f);
    int n = 0;
    const auto [cx, cy, cz] = cellOf(position[a]);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = cells.find(std::make_tuple(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (size_t b : it->second)
            if (b != a && glm::length(position[b] - position[a]) < near) mean += response[b], ++n;
        }
    if (n < 3) continue;
    mean /= float(n);
    const double deviation = double(glm::length(response[a] - mean) / glm::length(mean));
    const int edge = atlas.texels[o.active[a]].area < whole ? 1 : 0;
    sum[edge] += deviation * deviation, ++count[edge];
  }
  ASSERT_GT(count[0], 100);
  ASSERT_GT(count[1], 100);
  const double wholeRms = std::sqrt(sum[0] / count[0]), edgeRms = std::sqrt(sum[1] / count[1]);
  std::printf("texel %.4f units, %zu core texels: against their neighbours, RMS %.4f whole (%d), %.4f at a chart's edge (%d)\n",
              double(atlas.texel), core.size(), wholeRms, count[0], edgeRms, count[1]);
  EXPECT_LT(edgeRms, 0.008) << "the texels at a chart's edge stand out from their neighbours";
  EXPECT_LT(wholeRms, 0.008);
}

// Memory (docs/PRECOMPUTED.md, "Memory"): the precomputation holds at most the bytes it is given,
// counted as Object::bytes counts them, by taking a coarser texel where the kernels' taps (counted
// before any is computed) would not fit; the objects share the bytes by area. Below what an
// object's factors need, it fails with SS_LIMIT_EXCEEDED naming the object.
TEST(PrecomputedMemory, HoldsAtMostTheBytesItIsGiven) {
  testing::Sphere sphere(24, 12);
  Scene scene;
  scene.setMaterial(0, testing::skinMaterial(10.0f));
  scene.setMesh(3, sphere.desc(glm::vec3(0.0f), 0.3f, 0));
  scene.setMesh(7, sphere.desc(glm::vec3(1.0f, 0.0f, 0.0f), 0.2f, 0));
  scene.resolveMaterials();
  PrecomputedTransport unbounded;
  unbounded.precompute(scene, PrecomputedTransport::kDefaultBytes, {});
  const size_t all = unbounded.bytes();
  ASSERT_EQ(unbounded.objects().size(), 2u);
  size_t sum = 0;
  for (const auto& o : unbounded.objects()) sum += o.bytes();
  EXPECT_EQ(sum, all);
  for (double fraction : {0.5, 0.2}) {
    const size_t given = size_t(double(all) * fraction);
    PrecomputedTransport bounded;
    bounded.precompute(scene, given, {});
    std::printf("%.0f %% of %.1f MiB: %.1f MiB held; texels %.4f, %.4f (unbounded %.4f, %.4f)\n", 100 * fraction,
                double(all) / 1048576.0, double(bounded.bytes()) / 1048576.0, bounded.objects()[0].atlas.texel,
                bounded.objects()[1].atlas.texel, unbounded.objects()[0].atlas.texel, unbounded.objects()[1].atlas.texel);
    EXPECT_LE(bounded.bytes(), given) << fraction;
    ASSERT_EQ(bounded.objects().size(), 2u);
    for (size_t i = 0; i < 2; ++i) EXPECT_GT(bounded.objects()[i].atlas.texel, unbounded.objects()[i].atlas.texel);
  }
  PrecomputedTransport tiny;
  try {
    tiny.precompute(scene, 64 << 10, {});
    ADD_FAILURE() << "64 KiB held a precomputation";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), SS_LIMIT_EXCEEDED);
    EXPECT_NE(std::string(e.what()).find("PRECOMPUTED: object 3"), std::string::npos) << e.what();
  }
}

// Memory shared by area (docs/PRECOMPUTED.md, "Memory"): an object of many small charts (here 60
// cubes of 6 charts each, 0.03 units across, beside a sphere of radius 1) needs an atlas that no
// coarser texel makes smaller than its charts' borders; below its share by area (1 % of the 64 MiB)
// it takes the memory still left instead, and the sphere after it the rest. So too where the cubes
// lie close together and their factors alone exceed the share. (Until stop 48 both failed with
// SS_LIMIT_EXCEEDED, as PRECOMPUTED did on the heterogeneous example's bumpy monkey.)
TEST(PrecomputedMemory, AnObjectOfManyChartsTakesWhatTheOthersLeave) {
  for (float spacing : {1.5f, 0.06f}) {  // apart: the atlas exceeds the share; together: the factors
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    for (int i = 0; i < 60; ++i) {
      glm::vec3 lo(spacing * float(i % 8), spacing * float(i / 8), 0.0f);
      testing::Box box(lo, lo + glm::vec3(0.03f));
      uint32_t base = uint32_t(positions.size() / 3);
      positions.insert(positions.end(), box.positions.begin(), box.positions.end());
      for (uint32_t index : box.indices) indices.push_back(base + index);
    }
    SsMeshDesc cubes = testing::Box(glm::vec3(0.0f), glm::vec3(1.0f)).desc(0);
    cubes.positions = positions.data();
    cubes.vertex_count = uint32_t(positions.size() / 3);
    cubes.indices = indices.data();
    cubes.triangle_count = uint32_t(indices.size() / 3);
    testing::Sphere sphere(24, 12);
    Scene scene;
    scene.setMaterial(0, testing::skinMaterial(30.0f));
    scene.setMesh(2, cubes);  // first: its share is its area's, before the sphere takes any
    scene.setMesh(5, sphere.desc(glm::vec3(0.0f, 0.0f, -4.0f), 1.0f, 0));
    scene.resolveMaterials();
    const size_t given = size_t(64) << 20;
    const double cubesArea = 60 * 6 * 0.03 * 0.03, share = cubesArea / (cubesArea + 4.0 * M_PI * 0.99);
    PrecomputedTransport bounded;
    try {
      bounded.precompute(scene, given, {});
    } catch (const Error& e) {
      ADD_FAILURE() << "spacing " << spacing << ": " << e.what();
      continue;
    }
    ASSERT_EQ(bounded.objects().size(), 2u);
    const auto& many = bounded.objects()[0];
    std::printf("spacing %.2f: cubes %d charts, %zu bytes (%zu factors) at texel %.4f, their share by area %.0f; "
                "sphere %zu bytes\n",
                double(spacing), many.atlas.charts, many.bytes(), many.factor.size(), many.atlas.texel,
                share * double(given), bounded.objects()[1].bytes());
    EXPECT_GT(double(many.bytes()), 2.0 * share * double(given)) << spacing << ": the cubes kept to their share";
    EXPECT_GT(bounded.objects()[1].bytes(), 0u) << spacing;
    EXPECT_LE(bounded.bytes(), given) << spacing;
  }
}

// CI's part of bench/precomputed_heldout.sh (docs/PRECOMPUTED.md, "Held-out scenes"): the
// procedural test set's rod (scene 1: 7 mm of Apple under a spot, on a floor), which none of
// PRECOMPUTED's rules was chosen on, at the bench's 120 x 90 (at 64 x 48 FULL's own error hides
// it). It precomputes, relights without precomputing again, and its exitance is within 1.6 % of
// REFERENCE's: stop 49's changes (each texel's flux on the hats of every triangle it covers, lit
// at each part; the near kernels over each part's polygon; the factors without the profile's peak)
// took it from 6.1 % to 3.0 %, stop 51's texel of at most half an edge (kEdgeTexel, chosen on the
// calibration set) to 1.3 %. It is still a failure case kept in view, over FULL's 0.9 %: when that
// check fails, PRECOMPUTED has reached FULL here; run the bench again and update the document.
TEST(PrecomputedHeldOut, TheRodIsFurtherFromReferenceThanFull) {
  constexpr int kWidth = 120, kHeight = 90;  // the bench's size
  testing::EglContext gl;
  SsContext context = nullptr;
  ASSERT_EQ(ssNewContext(&context), SS_OK) << ssGetLastError();
  testing::ProceduralScene scene = testing::proceduralScene(testing::SceneSet::Test, 1, kWidth, kHeight);
  ASSERT_EQ(scene.apply(context), SS_OK) << ssGetLastError();
  // The exitance pass (what the translucency adds; the floor's shading is the same in both).
  auto render = [&](int method, std::vector<float>& exitance, SsStats& stats) {
    SsSettings settings = ssDefaultSettings();
    settings.method = method;
    settings.reference_samples = 50000;
    std::vector<float> rgba(size_t(kWidth) * kHeight * 4, 0.0f);
    exitance.assign(rgba.size(), 0.0f);
    ASSERT_EQ(ssSetSettings(context, &settings), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssRender(context, kWidth, kHeight, rgba.data()), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssGetPass(context, SS_PASS_EXITANCE, kWidth, kHeight, exitance.data()), SS_OK) << ssGetLastError();
    ASSERT_EQ(ssGetStats(context, &stats), SS_OK);
  };
  std::vector<float> full, precomputed, relit, reference;
  SsStats stats{};
  render(SS_METHOD_FULL, full, stats);
  render(SS_METHOD_PRECOMPUTED, precomputed, stats);
  EXPECT_EQ(stats.transport_reused, 0);
  render(SS_METHOD_PRECOMPUTED, relit, stats);
  EXPECT_EQ(stats.transport_reused, 1) << "the second frame precomputed again";
  render(SS_METHOD_REFERENCE, reference, stats);
  double fullError = testing::relativeRmse(full, reference), error = testing::relativeRmse(relit, reference);
  std::printf("%s: exitance against REFERENCE, FULL %.4f, PRECOMPUTED %.4f\n", scene.description.c_str(), fullError,
              error);
  EXPECT_LT(error, 0.016) << testing::writeComparison("precomputed_heldout_rod", relit, reference, kWidth, kHeight);
  EXPECT_GT(error, fullError) << "PRECOMPUTED is now within FULL's error on the held-out rod: update docs/PRECOMPUTED.md";
  ssReleaseContext(context);
}

// Per object (ssGetPrecomputedObjects): each translucent object's figures, which sum to the
// render's stats; a capacity smaller than the count writes that many; bad arguments are refused.
// The texel of an object mostly within one local range (a candle under wax's long red profile,
// modelled with vertices on its rims only: its local range is the profile's support, it has no
// global branch) is finer than kMaxRadius texels across that range, while all its kernels' taps
// stay within kSmallObjectTaps; a large object under the same profile keeps kMaxRadius.
TEST(PrecomputedSizes, ASmallObjectUnderALongProfileGetsAFinerTexel) {
  const double edge = 1.25, support = 1.9, detail = 0.02;  // scene units: wax_jade's candle's
  const size_t bytes = size_t(300) << 20;
  PrecomputationSize small = choosePrecomputation(12.0, edge, support, detail, bytes);
  PrecomputationSize large = choosePrecomputation(300.0, edge, support, detail, bytes);
  const double capped = support / PrecomputedTransport::kMaxRadius;
  std::printf("local range %.3g; texel: small object %.4g, large object %.4g (kMaxRadius's %.4g)\n",
              double(small.localRange), double(small.texel), double(large.texel), capped);
  ASSERT_FLOAT_EQ(small.localRange, float(support));
  EXPECT_LT(small.texel, 0.5 * capped) << "the small object's texel is held at kMaxRadius";
  const double texels = 1.8 * 12.0 / (double(small.texel) * small.texel) + 64.0;
  const double reach = support / small.texel + 0.5;
  EXPECT_LE(texels * std::min(M_PI * reach * reach, texels), PrecomputedTransport::kSmallObjectTaps * 1.0001);
  EXPECT_FLOAT_EQ(large.texel, float(capped)) << "a large object's texel moved";
}

TEST_F(Precomputed, ReportsEachObject) {
  testing::Sphere sphere(24, 12);
  SsMaterialDesc skin = testing::skinMaterial(30.0f), grey = testing::greyMaterial(0.5f);
  ASSERT_EQ(testing::setLitSphere(context, sphere, skin), SS_OK) << ssGetLastError();
  SsMeshDesc second = sphere.desc(glm::vec3(0.15f, 0.15f, -0.4f), 0.1f, 0), floor = sphere.desc(glm::vec3(0.0f, 0.0f, -2.0f), 1.0f, 1);
  ASSERT_EQ(ssSetMaterial(context, 1, &grey), SS_OK);
  ASSERT_EQ(ssSetMesh(context, 9, &second), SS_OK);
  ASSERT_EQ(ssSetMesh(context, 4, &floor), SS_OK);  // opaque: not precomputed
  uint32_t count = 99;
  ASSERT_EQ(ssGetPrecomputedObjects(context, nullptr, 0, &count), SS_OK);
  EXPECT_EQ(count, 0u) << "objects before any PRECOMPUTED render";
  SsStats stats{};
  render(SS_METHOD_PRECOMPUTED, 32, &stats);
  ASSERT_EQ(ssGetPrecomputedObjects(context, nullptr, 0, &count), SS_OK);
  ASSERT_EQ(count, 2u);
  SsPrecomputedObject objects[3]{};
  ASSERT_EQ(ssGetPrecomputedObjects(context, objects, 3, &count), SS_OK);
  EXPECT_EQ(objects[0].object_id, 0u);
  EXPECT_EQ(objects[1].object_id, 9u);
  uint64_t bytes = 0, texels = 0, factors = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const SsPrecomputedObject& o = objects[i];
    bytes += o.bytes, texels += o.texels, factors += o.factors;
    EXPECT_GT(o.vertices, 0u);
    EXPECT_GT(o.kernel_taps, o.texels);
    EXPECT_GT(o.atlas_width * o.atlas_height, 0);
    EXPECT_GT(o.texel_size, 0.0f);
    EXPECT_GE(o.local_range, o.texel_size);
    EXPECT_GT(o.precompute_ms, 0.0);
    EXPECT_GT(o.charts, 0);
    EXPECT_EQ(o.uv_charts, 0) << "a UV sphere's map is stretched at its poles";
    EXPECT_EQ(o.uv_islands_refused, 1);
  }
  EXPECT_EQ(bytes, stats.precomputed_bytes);
  EXPECT_EQ(texels, stats.precomputed_texels);
  EXPECT_EQ(factors, stats.precomputed_factors);
  SsPrecomputedObject one[1]{};
  ASSERT_EQ(ssGetPrecomputedObjects(context, one, 1, &count), SS_OK);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(one[0].object_id, 0u);
  EXPECT_EQ(ssGetPrecomputedObjects(context, nullptr, 1, &count), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssGetPrecomputedObjects(context, objects, 3, nullptr), SS_INVALID_ARGUMENT);
  EXPECT_EQ(ssGetPrecomputedObjects(nullptr, objects, 3, &count), SS_INVALID_HANDLE);
}

}  // namespace
}  // namespace subsplat
