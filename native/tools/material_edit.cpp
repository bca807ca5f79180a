// subsplat_material_edit: MATERIAL_EDIT against FULL on procedural scenes (docs/MATERIAL_EDIT.md).
// Per scene: the precomputation (a MATERIAL_EDIT render of the scene's material), then the issue's
// edits of every translucent material one after another (sigma_a x 2, sigma_s' x 0.5, another
// preset; each from the scene's own material), each a MATERIAL_EDIT render reusing the transport
// where it can, then FULL's renders of the scene's material and of each edited one: relative RMSE,
// wall times, fragment invocations and light views drawn, one JSON object per scene. The
// calibration set chooses the constants of the precomputation; the test set, never looked at while
// choosing them, is what docs/MATERIAL_EDIT.md reports.
//
//   subsplat_material_edit [--set calibration|test] [--first N] [--count N] [--size WxH]
//                          [--resolution N] [--images DIR]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"
#include "testing/procedural.h"
#include "testing/scenes.h"

namespace {

using subsplat::testing::SceneSet;

uint64_t fragments(const SsStats& s) {
  uint64_t sum = 0;
  for (uint64_t f : s.fragment_invocations) sum += f;
  return sum;
}

// The time of each stage (SS_STAGE_*: buffers, splatting, shading, read-back), a JSON array.
std::string stages(const SsStats& s) {
  std::string out = "[";
  char number[32];
  for (int k = 0; k < SS_STAGE_COUNT; ++k) {
    std::snprintf(number, sizeof number, "%s%.1f", k ? ", " : "", s.stage_ms[k]);
    out += number;
  }
  return out + "]";
}

bool render(SsContext context, int method, int width, int height, int resolution, std::vector<float>& rgba,
            SsStats& stats) {
  SsSettings settings = ssDefaultSettings();
  settings.method = method;
  settings.irradiance_resolution = resolution;
  settings.shadow_resolution = 1024;
  rgba.assign(size_t(width) * height * 4, 0.0f);
  if (ssSetSettings(context, &settings) != SS_OK || ssRender(context, width, height, rgba.data()) != SS_OK ||
      ssGetStats(context, &stats) != SS_OK) {
    std::fprintf(stderr, "subsplat_material_edit: %s\n", ssGetLastError());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  SceneSet set = SceneSet::Test;
  int first = 0, count = 6, width = 120, height = 90, resolution = 0;
  std::string images;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "subsplat_material_edit: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--set") set = next() == "calibration" ? SceneSet::Calibration : SceneSet::Test;
    else if (a == "--first") first = std::atoi(next().c_str());
    else if (a == "--count") count = std::atoi(next().c_str());
    else if (a == "--size") std::sscanf(next().c_str(), "%dx%d", &width, &height);
    else if (a == "--resolution") resolution = std::atoi(next().c_str());
    else if (a == "--images") images = next();
    else {
      std::fprintf(stderr, "usage: subsplat_material_edit [--set calibration|test] [--first N] [--count N] "
                           "[--size WxH] [--resolution N (0: automatic)] [--images DIR (each edit, FULL's image and their difference)]\n");
      return 2;
    }
  }
  if (!images.empty()) setenv("SUBSPLAT_TEST_OUTPUT", images.c_str(), 1);  // testing::writeComparison's folder
  subsplat::testing::EglContext gl;
  std::printf("[\n");
  for (int index = first; index < first + count; ++index) {
    SsContext context = nullptr;
    if (ssNewContext(&context) != SS_OK) return 1;
    subsplat::testing::ProceduralScene scene = subsplat::testing::proceduralScene(set, index, width, height);
    if (scene.apply(context) != SS_OK) return 1;
    std::vector<float> edit, full;
    SsStats editStats{}, fullStats{};
    // The precomputation, then the edits one after another (as a slider drags), then FULL's renders
    // of the scene's own material and of each edited one.
    if (!render(context, SS_METHOD_MATERIAL_EDIT, width, height, resolution, edit, editStats)) return 1;
    const SsStats precomputation = editStats;
    const std::vector<float> precomputed = edit;
    const char* names[3] = {"sigma_a x2", "sigma_s' x0.5", "Skin2"};
    // Sets the scene's translucent materials to edit e (-1: their own).
    auto setEdit = [&](int e) {
      for (size_t m = 0; m < scene.materials.size(); ++m) {
        SsMaterialDesc d = scene.materials[m];
        if (d.kind == SS_MATERIAL_DIPOLE && e == 0) for (float& a : d.sigma_a) a *= 2.0f;
        if (d.kind == SS_MATERIAL_DIPOLE && e == 1) for (float& s : d.sigma_s_prime) s *= 0.5f;
        if (d.kind == SS_MATERIAL_DIPOLE && e == 2)
          for (const subsplat::testing::PresetMedium& p : subsplat::testing::kPresetMedia)
            if (std::strcmp(p.name, "Skin2") == 0) {
              std::memcpy(d.sigma_a, p.sigmaA, sizeof d.sigma_a);
              std::memcpy(d.sigma_s_prime, p.sigmaSPrime, sizeof d.sigma_s_prime);
            }
        if (ssSetMaterial(context, uint32_t(m), &d) != SS_OK) return false;
      }
      return true;
    };
    std::vector<float> edits[3];
    SsStats editsStats[3]{};
    for (int e = 0; e < 3; ++e)
      if (!setEdit(e) || !render(context, SS_METHOD_MATERIAL_EDIT, width, height, resolution, edits[e], editsStats[e]))
        return 1;
    if (!setEdit(-1) || !render(context, SS_METHOD_FULL, width, height, resolution, full, fullStats)) return 1;
    std::printf("%s{\"set\": \"%s\", \"index\": %d, \"scene\": \"%s\",\n  \"precompute_ms\": %.1f, "
                "\"precompute_fragments\": %llu, \"full_ms\": %.1f, \"full_fragments\": %llu, \"error\": %.5f,\n"
                "  \"precompute_stage_ms\": %s, \"full_stage_ms\": %s, \"irradiance_resolution\": %d,\n"
                "  \"edits\": [",
                index == first ? "" : ",\n", subsplat::testing::setName(set), index, scene.description.c_str(),
                precomputation.precompute_ms, (unsigned long long)fragments(precomputation), fullStats.frame_ms,
                (unsigned long long)fragments(fullStats), subsplat::testing::relativeRmse(precomputed, full),
                stages(precomputation).c_str(), stages(fullStats).c_str(), precomputation.irradiance_resolution);
    for (int e = 0; e < 3; ++e) {
      if (!setEdit(e) || !render(context, SS_METHOD_FULL, width, height, resolution, full, fullStats)) return 1;
      const SsStats& s = editsStats[e];
      std::printf("%s\n    {\"edit\": \"%s\", \"reused\": %d, \"edit_ms\": %.1f, \"edit_fragments\": %llu, "
                  "\"edit_light_views\": %d, \"edit_stage_ms\": %s, \"full_ms\": %.1f, \"full_fragments\": %llu, \"error\": %.5f}",
                  e == 0 ? "" : ",", names[e], s.transport_reused, s.frame_ms, (unsigned long long)fragments(s),
                  s.light_views, stages(s).c_str(), fullStats.frame_ms, (unsigned long long)fragments(fullStats),
                  subsplat::testing::relativeRmse(edits[e], full));
      if (!images.empty())
        subsplat::testing::writeComparison(std::string(subsplat::testing::setName(set)) + "_" + std::to_string(index) +
                                               "_edit" + std::to_string(e),
                                           edits[e], full, width, height);
    }
    std::printf("]}");
    std::fflush(stdout);
    ssReleaseContext(context);
  }
  std::printf("\n]\n");
  return 0;
}
