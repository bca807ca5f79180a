// subsplat_tessellation: PRECOMPUTED's error against REFERENCE as the mesh of one object changes
// (docs/PRECOMPUTED.md, "The candle's texel"). The native tests' lit Skin1 sphere (testing::
// setLitSphere: radius 0.3, a sun and a point light) as a UV sphere of 24, 48 and 96 segments, whose
// poles are fans of thin triangles, and as an icosphere split 3 and 4 times, whose triangles are
// well shaped. Per mesh and scale: the object's sizes (ssGetPrecomputedObjects) and the exitance's
// relative RMSE against REFERENCE's (100 000 samples) for PRECOMPUTED and for FULL.
//
//   subsplat_tessellation [--size N] [--images DIR (|PRECOMPUTED - REFERENCE| per mesh)]
#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace {

// An icosahedron split `levels` times (each triangle into four), on the unit sphere.
subsplat::testing::Sphere icosphere(int levels) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6,
                             7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  for (glm::vec3& p : v) p = glm::normalize(p);
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> middle;
    auto middleOf = [&](uint32_t a, uint32_t b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto found = middle.find(key);
      if (found != middle.end()) return found->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return middle[key] = uint32_t(v.size() - 1);
    };
    std::vector<uint32_t> split;
    for (size_t i = 0; i < f.size(); i += 3) {
      uint32_t a = f[i], b = f[i + 1], c = f[i + 2], ab = middleOf(a, b), bc = middleOf(b, c), ca = middleOf(c, a);
      split.insert(split.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f.swap(split);
  }
  subsplat::testing::Sphere sphere(4, 2);
  sphere.positions.clear(), sphere.normals.clear(), sphere.uvs.clear();
  for (const glm::vec3& p : v) {
    sphere.positions.insert(sphere.positions.end(), {p.x, p.y, p.z});
    sphere.normals.insert(sphere.normals.end(), {p.x, p.y, p.z});
    sphere.uvs.insert(sphere.uvs.end(), {0.0f, 0.0f});  // (a homogeneous material reads none)
  }
  sphere.indices = f;
  return sphere;
}

bool render(SsContext context, int method, int size, std::vector<float>& exitance) {
  SsSettings settings = ssDefaultSettings();
  settings.method = method;
  settings.reference_samples = 100000;
  std::vector<float> rgba(size_t(size) * size * 4);
  exitance.assign(rgba.size(), 0.0f);
  if (ssSetSettings(context, &settings) != SS_OK || ssRender(context, size, size, rgba.data()) != SS_OK ||
      ssGetPass(context, SS_PASS_EXITANCE, size, size, exitance.data()) != SS_OK) {
    std::fprintf(stderr, "subsplat_tessellation: %s\n", ssGetLastError());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  int size = 64;
  std::string images;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--size" && i + 1 < argc) {
      size = std::atoi(argv[++i]);
    } else if (a == "--images" && i + 1 < argc) {
      images = argv[++i];
    } else {
      std::fprintf(stderr, "usage: subsplat_tessellation [--size N] [--images DIR]\n");
      return 2;
    }
  }
  if (size < 8) size = 8;
  if (!images.empty()) setenv("SUBSPLAT_TEST_OUTPUT", images.c_str(), 1);  // testing::writeComparison's folder
  subsplat::testing::EglContext gl;
  struct Mesh {
    std::string name;
    subsplat::testing::Sphere sphere;
  };
  std::vector<Mesh> meshes = {{"uv24", subsplat::testing::Sphere(24, 12)},
                              {"uv48", subsplat::testing::Sphere(48, 24)},
                              {"uv96", subsplat::testing::Sphere(96, 48)},
                              {"ico3", icosphere(3)},
                              {"ico4", icosphere(4)}};
  std::printf("mesh | mm per unit | vertices | texel | local range | factors | exitance vs REFERENCE: PRECOMPUTED, FULL\n");
  for (float mm : {30.0f, 10.0f})
    for (const Mesh& mesh : meshes) {
      SsContext context = nullptr;
      if (ssNewContext(&context) != SS_OK) return 1;
      if (subsplat::testing::setLitSphere(context, mesh.sphere, subsplat::testing::skinMaterial(mm)) != SS_OK) {
        std::fprintf(stderr, "subsplat_tessellation: %s\n", ssGetLastError());
        return 1;
      }
      std::vector<float> precomputed, full, reference;
      SsPrecomputedObject object{};
      uint32_t count = 0;
      if (!render(context, SS_METHOD_PRECOMPUTED, size, precomputed) ||
          ssGetPrecomputedObjects(context, &object, 1, &count) != SS_OK || count != 1 ||
          !render(context, SS_METHOD_FULL, size, full) || !render(context, SS_METHOD_REFERENCE, size, reference)) {
        // (a mesh whose precomputation exceeds the memory budget is said so and skipped)
        std::printf("%s | %.0f | not rendered: %s\n", mesh.name.c_str(), double(mm), ssGetLastError());
        ssReleaseContext(context);
        continue;
      }
      std::printf("%s | %.0f | %u | %.4g | %.4g | %llu | %.4f, %.4f\n", mesh.name.c_str(), double(mm), object.vertices,
                  double(object.texel_size), double(object.local_range), (unsigned long long)object.factors,
                  subsplat::testing::relativeRmse(precomputed, reference), subsplat::testing::relativeRmse(full, reference));
      std::fflush(stdout);
      if (!images.empty())
        subsplat::testing::writeComparison("tessellation_" + mesh.name + "_" + std::to_string(int(mm)), precomputed,
                                           reference, size, size);
      ssReleaseContext(context);
    }
  return 0;
}
