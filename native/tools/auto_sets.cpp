// subsplat_auto_sets: the automatic quality on procedural scenes it was not fitted on
// (docs/AUTO.md, "Held-out scenes"). Two disjoint sets of scenes (native/src/testing/procedural.h):
//
//   --rungs (calibration)  MULTIRES at every rung of the automatic resolution's ladder up to a
//                          quarter of the scene's reference resolution (testing::referenceResolution),
//                          and at that; per point the coarsest light texel, the materials' energy
//                          radii, a pixel's size and the error the rung adds over the reference's,
//                          for bench/auto_fit.py.
//   default (test)         AUTO at the target: the resolution it chooses, and whether the library
//                          says the target can be met; MULTIRES at that resolution and at the
//                          reference's, and FULL at it (the image AUTO renders).
//
// The error a resolution adds over a converged one is bounded by its image's relative RMSE against
// the converged image (the triangle inequality), so no REFERENCE is needed.
//
//   subsplat_auto_sets [--set calibration|test] [--first N] [--count N] [--size WxH]
//                      [--target E] [--rungs] [--reference N] [--list] [--json FILE] [--images DIR]
//                      [--save DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace {

using subsplat::testing::SceneSet;

using subsplat::testing::kRungs;
// Energy fractions whose radii the calibration reports (R_P is 0.95's).
constexpr double kEnergies[] = {0.25, 0.5, 0.75, 0.95};

[[noreturn]] void usage(const std::string& problem) {
  if (!problem.empty()) std::fprintf(stderr, "subsplat_auto_sets: %s\n\n", problem.c_str());
  std::fprintf(stderr,
               "usage: subsplat_auto_sets [options]\n"
               "  --set calibration|test  which set (default test)\n"
               "  --first N, --count N    scenes N.. of the set (default 0, 12)\n"
               "  --size WxH              frame size (default 120x90)\n"
               "  --target E              the automatic resolution's target error (default 0.01)\n"
               "  --rungs                 every rung against the converged reference (calibration), not AUTO\n"
               "  --reference N           also REFERENCE with N surface samples: AUTO's error over the reference\n"
               "                          resolution's, both against it (the issue's measure)\n"
               "  --list                  print the scenes' descriptions only\n"
               "  --save DIR              write each scene as DIR/<set>_<index>.ssscene for subsplat_replay, and\n"
               "                          render nothing\n"
               "  --json FILE             write every figure as JSON\n"
               "  --images DIR            write each scene's image at AUTO's resolution (--rungs: at each rung), the\n"
               "                          reference's and their difference (PNG)\n");
  std::exit(2);
}

bool check(SsStatus status, const char* what) {
  if (status == SS_OK) return true;
  std::fprintf(stderr, "subsplat_auto_sets: %s: %s\n", what, ssGetLastError());
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  SceneSet set = SceneSet::Test;
  int first = 0, count = 12, width = 120, height = 90;
  float target = 0.01f;
  bool rungs = false, list = false;
  uint32_t referenceSamples = 0;
  std::string json, images, save;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--set") {
      std::string s = value();
      if (s == "calibration") set = SceneSet::Calibration;
      else if (s == "test") set = SceneSet::Test;
      else usage("--set: calibration or test");
    } else if (a == "--first") first = std::atoi(value().c_str());
    else if (a == "--count") count = std::atoi(value().c_str());
    else if (a == "--size") {
      std::string s = value();
      if (std::sscanf(s.c_str(), "%dx%d", &width, &height) != 2 || width < 16 || height < 16 || width > 4096 || height > 4096)
        usage("--size WxH, 16 to 4096");
    } else if (a == "--target") target = std::strtof(value().c_str(), nullptr);
    else if (a == "--rungs") rungs = true;
    else if (a == "--list") list = true;
    else if (a == "--reference") referenceSamples = uint32_t(std::strtoul(value().c_str(), nullptr, 10));
    else if (a == "--json") json = value();
    else if (a == "--images") images = value();
    else if (a == "--save") save = value();
    else if (a == "--help" || a == "-h") usage("");
    else usage("unknown option " + a);
  }
  if (first < 0 || count < 1 || !(target >= 1e-3f && target <= 0.5f)) usage("--first >= 0, --count >= 1, --target in [0.001, 0.5]");
  if (!images.empty()) setenv("SUBSPLAT_TEST_OUTPUT", images.c_str(), 1);
  if (list) {
    for (int index = first; index < first + count; ++index)
      std::printf("%3d  %s\n", index, subsplat::testing::proceduralScene(set, index, width, height).description.c_str());
    return 0;
  }

  subsplat::testing::EglContext gl;
  SsContext context = nullptr;
  if (!check(ssNewContext(&context), "ssNewContext")) return 1;
  std::printf("# %s set, scenes %d-%d, %dx%d, target %.4g, %s\n", subsplat::testing::setName(set), first, first + count - 1,
              width, height, target, gl.renderer().c_str());
  std::ostringstream out;
  out << "{\"set\": \"" << subsplat::testing::setName(set) << "\", \"width\": " << width << ", \"height\": " << height
      << ", \"target\": " << target << ", \"energies\": [";
  for (double e : kEnergies) out << (e == kEnergies[0] ? "" : ", ") << e;
  out << "], \"scenes\": [";
  int missed = 0, unreachable = 0;
  for (int index = first; index < first + count; ++index) {
    subsplat::testing::ProceduralScene scene = subsplat::testing::proceduralScene(set, index, width, height);
    if (!check(scene.apply(context), scene.description.c_str())) return 1;
    std::printf("%3d  %s\n", index, scene.description.c_str());
    if (!save.empty()) {
      std::string path = save + "/" + subsplat::testing::setName(set) + "_" + std::to_string(index) + ".ssscene";
      if (!check(ssSaveScene(context, path.c_str()), path.c_str())) return 1;
      continue;
    }
    out << (index > first ? ", " : "") << "{\"index\": " << index << ", \"seed\": " << scene.seed << ", \"description\": \""
        << scene.description << "\", \"radius\": " << scene.radius
        << ", \"pixel\": " << scene.pixel << ", \"radii\": [";
    for (double e : kEnergies) out << (e == kEnergies[0] ? "" : ", ") << subsplat::testing::shortestRadius(scene, e);
    out << "], ";
    std::vector<float> finest, image, full;
    SsStats finestStats{}, stats{}, fullStats{};
    using subsplat::testing::renderAt;
    if (rungs) {
      // The rungs up to a quarter of the reference's, the reference converged (kReferenceTexels).
      if (!check(renderAt(context, SS_METHOD_MULTIRES, width, height, kRungs[0], target, image, stats), "MULTIRES at 128")) return 1;
      int reference = subsplat::testing::referenceResolution(kRungs[0], stats.texels_per_range);
      if (!check(renderAt(context, SS_METHOD_MULTIRES, width, height, reference, target, finest, finestStats), "the reference")) return 1;
      out << "\"reference\": " << reference << ", \"points\": [";
      for (int rung : kRungs) {
        if (4 * rung > reference) break;
        if (rung > kRungs[0] && !check(renderAt(context, SS_METHOD_MULTIRES, width, height, rung, target, image, stats), "a rung"))
          return 1;
        double added = subsplat::testing::relativeRmse(image, finest);
        double texel = stats.texels_per_range > 0.0f ? subsplat::testing::shortestRadius(scene, 0.95) / stats.texels_per_range : 0.0;
        std::printf("     %4d: %6.2f texels per R_P, adds %.4f over %d\n", rung, stats.texels_per_range, added, reference);
        if (!images.empty())
          subsplat::testing::writeComparison(std::string("rung_") + subsplat::testing::setName(set) + "_" + std::to_string(index) + "_" +
                                                 std::to_string(rung), image, finest, width, height);
        out << (rung > kRungs[0] ? ", " : "") << "{\"resolution\": " << rung << ", \"texel\": " << texel
            << ", \"added\": " << added << "}";
      }
      out << "]}";
      std::fflush(stdout);
      continue;
    }
    // AUTO as a user gets it (FULL), then MULTIRES at its resolution and at the reference's.
    if (!check(renderAt(context, SS_METHOD_FULL, width, height, 0, target, full, fullStats), "AUTO")) return 1;
    int chosen = fullStats.irradiance_resolution;
    bool reachable = fullStats.target_reachable != 0;
    int reference = subsplat::testing::referenceResolution(chosen, fullStats.texels_per_range);
    double texel = fullStats.texels_per_range > 0.0f ? subsplat::testing::shortestRadius(scene, 0.95) / fullStats.texels_per_range : 0.0;
    out << "\"resolution\": " << chosen << ", \"reference\": " << reference << ", \"texel\": " << texel << ", \"texels_per_range\": "
        << fullStats.texels_per_range << ", \"reachable\": " << (reachable ? "true" : "false");
    unreachable += !reachable;
    if (reference <= chosen) {  // AUTO at the largest buffer: nothing finer to measure against
      std::printf("     AUTO %4d: %6.2f texels per R_P; not measured (no finer buffer)%s\n", chosen, fullStats.texels_per_range,
                  !reachable ? "; the library says the target cannot be met" : "");
      out << "}";
      std::fflush(stdout);
      continue;
    }
    if (!check(renderAt(context, SS_METHOD_MULTIRES, width, height, chosen, target, image, stats), "MULTIRES at AUTO's")) return 1;
    if (!check(renderAt(context, SS_METHOD_MULTIRES, width, height, reference, target, finest, finestStats), "the reference")) return 1;
    double added = subsplat::testing::relativeRmse(image, finest), fullAdded = subsplat::testing::relativeRmse(full, finest);
    double referenceAdded = -1.0, referenceError = -1.0;
    if (referenceSamples > 0) {  // the measure: AUTO's error against REFERENCE over the converged buffer's
      SsSettings settings = ssDefaultSettings();
      settings.method = SS_METHOD_REFERENCE;
      settings.reference_samples = referenceSamples;
      std::vector<float> truth(size_t(width) * height * 4);
      if (!check(ssSetSettings(context, &settings), "REFERENCE settings") || !check(ssRender(context, width, height, truth.data()), "REFERENCE"))
        return 1;
      referenceError = subsplat::testing::relativeRmse(finest, truth);
      referenceAdded = subsplat::testing::relativeRmse(image, truth) - referenceError;
      std::printf("     against REFERENCE (%u samples): the reference resolution %.4f, AUTO's adds %.4f\n", referenceSamples,
                  referenceError, referenceAdded);
    }
    bool miss = reachable && added > target;
    missed += miss;
    std::printf("     AUTO %4d: %6.2f texels per R_P; the resolution adds %.4f over %d (FULL at it: %.4f)%s\n", chosen,
                fullStats.texels_per_range, added, reference, fullAdded, miss ? "  MISSED" : "");
    std::fflush(stdout);
    if (!images.empty())
      subsplat::testing::writeComparison(std::string("auto_") + subsplat::testing::setName(set) + "_" + std::to_string(index), image,
                                         finest, width, height);
    out << ", \"added\": " << added << ", \"full_added\": " << fullAdded << ", \"reference_error\": " << referenceError
        << ", \"reference_added\": " << referenceAdded << "}";
  }
  out << "]";
  if (!save.empty()) {  // nothing was rendered
    std::printf("# %d scenes written to %s\n", count, save.c_str());
    ssReleaseContext(context);
    return 0;
  }
  if (!rungs) {
    std::printf("# %d of %d scenes over the target where the library said it could be met; %d said unreachable\n", missed, count,
                unreachable);
    out << ", \"missed\": " << missed << ", \"unreachable\": " << unreachable;
  }
  out << "}\n";
  if (!json.empty()) std::ofstream(json) << out.str();
  ssReleaseContext(context);
  return missed ? 3 : 0;
}
