// subsplat_replay: renders scene files (ssSaveScene, written by the add-on)
// through the C API in its own surfaceless EGL context, without Blender. It is
// the native half of bench/methods.py: every method, round-robin, median frame
// time, GL time and fragment invocations per stage and per splatting level,
// and relative RMSE against REFERENCE. Prints a table; --json writes the
// figures for bench/replay.py, --images writes PFM images.
//
//   subsplat_replay [options] SCENE.ssscene...  (subsplat_replay --help)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "subsplat/subsplat.h"
#include "testing/egl_context.h"

namespace {

const char* const kMethodNames[] = {"BRUTE", "MULTIRES", "ADAPTIVE", "FULL", "REFERENCE", "MATERIAL_EDIT", "PRECOMPUTED"};
const char* const kStageNames[] = {"buffers", "splatting", "shading", "readback"};

// A method, optionally with its own level count and epsilon: "FULL:0" is FULL with
// automatic levels, "FULL:3@0.01" FULL with 3 levels and epsilon 0.01.
struct Variant {
  int method = 0;
  int levels = -1;        // -1: --levels, else as saved
  float epsilon = 0.0f;   // 0: --epsilon, else as saved
  std::string label;
};

Variant variant(int method, int levels = -1) {
  std::string label = kMethodNames[method];
  if (levels >= 0) label += ":" + std::to_string(levels);
  return {method, levels, 0.0f, label};
}

struct Options {
  std::vector<std::string> scenes;
  std::vector<Variant> methods{variant(SS_METHOD_BRUTE), variant(SS_METHOD_MULTIRES), variant(SS_METHOD_ADAPTIVE),
                               variant(SS_METHOD_FULL)};
  int runs = 3;
  int warmup = 0;  // frames per method rendered first and not counted
  int width = 0, height = 0;  // 0: the frame size saved in the file
  int levels = -1;            // -1: as saved
  int irradianceResolution = -1;      // -1: as saved; 0: automatic
  float epsilon = 0.0f, alpha = 0.0f, z0 = 0.0f, targetError = 0.0f;  // 0: as saved
  uint32_t referenceSamples = 0;
  int atlas = -1;  // PRECOMPUTED's atlas: -1 as saved, else SS_ATLAS_*
  int forwardShift = -1;  // -1 as saved, else SS_FORWARD_SHIFT_*
  bool reference = true;
  double budget = 0.0;  // splatting budget per render, millions of fragment invocations; 0: none
  std::string json, images;
};

[[noreturn]] void usage(const std::string& problem) {
  if (!problem.empty()) std::fprintf(stderr, "subsplat_replay: %s\n\n", problem.c_str());
  std::fprintf(stderr,
               "usage: subsplat_replay [options] SCENE.ssscene...\n"
               "  --methods LIST          comma-separated, from BRUTE,MULTIRES,ADAPTIVE,FULL (default: all four),\n"
               "                          MATERIAL_EDIT, PRECOMPUTED (their first render precomputes: give\n"
               "                          --warmup 1 to time the renders that reuse it);\n"
               "                          METHOD:N gives that entry N levels (FULL:0: FULL with automatic levels),\n"
               "                          METHOD[:N]@E epsilon E (FULL:3@0.01)\n"
               "  --runs N                renders per method, round-robin (default 3)\n"
               "  --warmup N              renders per method before those, not counted (default 0)\n"
               "  --size WxH              frame size (default: the size saved with the scene)\n"
               "  --levels N              0 automatic, 1-8 forced (default: as saved)\n"
               "  --irradiance N|auto     irradiance buffer resolution, or automatic (default: as saved)\n"
               "  --target-error E        automatic resolution's target relative RMSE (default: as saved)\n"
               "  --epsilon E, --alpha A  eq. 14's epsilon and eq. 11's alpha (default: as saved)\n"
               "  --z0 F                  adaptive depth threshold z0 as a factor of the bounding radius\n"
               "  --budget M              splatting budget per render (ssSetSplatBudget), millions of fragment\n"
               "                          invocations: each frame is rendered again until complete, as the\n"
               "                          viewport does, and each run reports its renders (docs/VIEWPORT.md)\n"
               "  --no-reference          skip REFERENCE and the error columns\n"
               "  --reference-samples N   REFERENCE surface samples (default: as saved)\n"
               "  --atlas uv|made         PRECOMPUTED's atlas: the meshes' UV maps where they fit, or made\n"
               "                          as for meshes without (default: as saved)\n"
               "  --forward-shift on|off  the TABULATED model's forward shift (default: as saved)\n"
               "  --json FILE             write every figure as JSON\n"
               "  --images DIR            write each method's image and exitance pass as\n"
               "                          DIR/<scene>_<method>.pfm and DIR/<scene>_<method>_exitance.pfm\n");
  std::exit(2);
}

int parseInt(const std::string& text, const char* what) {
  char* end = nullptr;
  long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < 0 || value > 1 << 30) usage(std::string("bad ") + what + ": " + text);
  return int(value);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--methods") {
      o.methods.clear();
      std::stringstream list(value());
      for (std::string entry; std::getline(list, entry, ',');) {
        size_t at = entry.find('@');
        std::string head = entry.substr(0, at);
        std::string name = head.substr(0, head.find(':'));
        // REFERENCE is the errors' measure, rendered once after the runs (--no-reference skips it).
        auto it = std::find_if(std::begin(kMethodNames), std::end(kMethodNames),
                               [&](const char* m) { return name == m && name != "REFERENCE"; });
        if (it == std::end(kMethodNames)) usage("unknown method " + name);
        int levels = -1;
        if (head.find(':') != std::string::npos) levels = parseInt(head.substr(head.find(':') + 1), "levels");
        if (levels > 8) usage("levels of " + entry + " must be in [0, 8]");
        Variant v = variant(int(it - std::begin(kMethodNames)), levels);
        if (at != std::string::npos) {
          std::string text = entry.substr(at + 1);
          char* end = nullptr;
          v.epsilon = std::strtof(text.c_str(), &end);
          if (text.empty() || *end != '\0' || !(v.epsilon > 0.0f)) usage("bad epsilon in " + entry);
          v.label = entry;
        }
        o.methods.push_back(v);
      }
    } else if (a == "--warmup") {
      o.warmup = parseInt(value(), "warm-up frames");
    } else if (a == "--runs") {
      o.runs = std::max(1, parseInt(value(), "run count"));
    } else if (a == "--size") {
      std::string s = value();
      size_t x = s.find('x');
      if (x == std::string::npos) usage("--size wants WxH, got " + s);
      o.width = parseInt(s.substr(0, x), "width");
      o.height = parseInt(s.substr(x + 1), "height");
    } else if (a == "--levels") {
      o.levels = parseInt(value(), "levels");
    } else if (a == "--irradiance") {
      std::string text = value();
      o.irradianceResolution = text == "auto" ? 0 : parseInt(text, "irradiance resolution");
    } else if (a == "--epsilon" || a == "--alpha" || a == "--z0" || a == "--target-error") {
      std::string text = value();
      char* end = nullptr;
      float v = std::strtof(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !(v > 0.0f)) usage("bad " + a + ": " + text);
      (a == "--epsilon" ? o.epsilon : a == "--alpha" ? o.alpha : a == "--z0" ? o.z0 : o.targetError) = v;
    } else if (a == "--budget") {
      std::string text = value();
      char* end = nullptr;
      o.budget = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !(o.budget >= 0.0) || o.budget > 1e9) usage("bad --budget: " + text);
    } else if (a == "--no-reference") {
      o.reference = false;
    } else if (a == "--reference-samples") {
      o.referenceSamples = uint32_t(parseInt(value(), "reference samples"));
    } else if (a == "--atlas") {
      std::string text = value();
      if (text != "uv" && text != "made") usage("--atlas wants uv or made, got " + text);
      o.atlas = text == "uv" ? SS_ATLAS_UV_MAP : SS_ATLAS_MADE;
    } else if (a == "--forward-shift") {
      std::string text = value();
      if (text != "on" && text != "off") usage("--forward-shift wants on or off, got " + text);
      o.forwardShift = text == "on" ? SS_FORWARD_SHIFT_ON : SS_FORWARD_SHIFT_OFF;
    } else if (a == "--json") {
      o.json = value();
    } else if (a == "--images") {
      o.images = value();
    } else if (a == "-h" || a == "--help") {
      usage("");
    } else if (!a.empty() && a[0] == '-') {
      usage("unknown option " + a);
    } else {
      o.scenes.push_back(a);
    }
  }
  if (o.scenes.empty()) usage("no scene file given");
  return o;
}

struct Failure {
  std::string message;
};

void check(SsStatus status, const std::string& what) {
  if (status != SS_OK) throw Failure{what + ": " + ssGetLastError()};
}

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba, exitance;
};

struct Errors {
  double radiance = 0.0, exitance = 0.0;
  long pixels = 0;
};

// As tests/blender/accuracy.py compare(): over pixels both mark translucent,
// sqrt(mean (I - R)^2) / sqrt(mean R^2) over rgb, of radiance and of exitance.
Errors compare(const Image& image, const Image& reference) {
  double d2 = 0, r2 = 0, e2 = 0, b2 = 0;
  Errors errors;
  for (size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
    if (image.exitance[i + 3] <= 0.5f || reference.exitance[i + 3] <= 0.5f) continue;
    ++errors.pixels;
    for (int c = 0; c < 3; ++c) {
      d2 += std::pow(double(image.rgba[i + c]) - reference.rgba[i + c], 2);
      r2 += std::pow(double(reference.rgba[i + c]), 2);
      e2 += std::pow(double(image.exitance[i + c]) - reference.exitance[i + c], 2);
      b2 += std::pow(double(reference.exitance[i + c]), 2);
    }
  }
  errors.radiance = r2 > 0 ? std::sqrt(d2 / r2) : 0.0;
  errors.exitance = b2 > 0 ? std::sqrt(e2 / b2) : 0.0;
  return errors;
}

void writePfm(const std::string& path, int width, int height, const std::vector<float>& rgba) {
  std::ofstream out(path, std::ios::binary);
  out << "PF\n" << width << " " << height << "\n-1.0\n";  // little-endian, bottom row first
  for (size_t i = 0; i < rgba.size(); i += 4) out.write(reinterpret_cast<const char*>(&rgba[i]), 12);
  if (!out) throw Failure{"cannot write " + path};
}

// The image and its exitance pass (B of eq. 5) as <stem>.pfm and <stem>_exitance.pfm.
void writeImages(const std::string& stem, const Image& image) {
  writePfm(stem + ".pfm", image.width, image.height, image.rgba);
  writePfm(stem + "_exitance.pfm", image.width, image.height, image.exitance);
}

// The renders of one frame under a splatting budget (--budget).
struct BudgetRun {
  int renders = 0;
  double firstMs = 0.0, longestMs = 0.0, totalMs = 0.0;
  uint64_t mostSplatFragments = 0;  // of one render, its splat draws (eq. 17's accumulation not counted)
};

struct Result {
  Variant variant;
  std::vector<SsStats> runs;
  std::vector<BudgetRun> budgetRuns;  // --budget: each run's renders
  SsStats fastest{};
  double medianMs = 0.0;
  Errors errors;
  bool hasErrors = false;
};

std::string baseName(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  return name.substr(0, name.find('.'));
}

std::string cpuName() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

std::string jsonEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

// The saved settings with the command line's and the entry's overrides.
SsSettings settingsFor(const SsSettings& saved, const Options& options, const Variant& entry) {
  SsSettings settings = saved;
  settings.method = entry.method;
  if (entry.levels >= 0)
    settings.levels = entry.levels;
  else if (options.levels >= 0)
    settings.levels = options.levels;
  if (entry.epsilon > 0.0f)
    settings.epsilon = entry.epsilon;
  else if (options.epsilon > 0.0f)
    settings.epsilon = options.epsilon;
  if (options.irradianceResolution >= 0) settings.irradiance_resolution = options.irradianceResolution;
  if (options.alpha > 0.0f) settings.alpha = options.alpha;
  if (options.z0 > 0.0f) settings.z0_factor = options.z0;
  if (options.targetError > 0.0f) settings.target_error = options.targetError;
  if (options.referenceSamples > 0) settings.reference_samples = options.referenceSamples;
  if (options.atlas >= 0) settings.precomputed_atlas = options.atlas;
  if (options.forwardShift >= 0) settings.forward_shift = options.forwardShift;
  return settings;
}

// One frame with its exitance pass and stats; with a budget, rendered until complete (the stats
// are the last render's, frame_ms all of them together).
Image render(SsContext context, const SsSettings& settings, int width, int height, const std::string& label,
             SsStats& stats, double budget = 0.0, BudgetRun* run = nullptr) {
  check(ssSetSettings(context, &settings), "settings of " + label);
  check(ssSetSplatBudget(context, uint64_t(budget * 1e6)), "budget of " + label);
  Image image;
  image.width = width, image.height = height;
  image.rgba.resize(size_t(width) * height * 4);
  image.exitance.resize(image.rgba.size());
  BudgetRun local;
  BudgetRun& r = run ? *run : local;
  r = BudgetRun{};
  for (;;) {
    check(ssRender(context, width, height, image.rgba.data()), "rendering " + label);
    check(ssGetStats(context, &stats), "stats of " + label);
    uint64_t splatted = 0;
    for (int k = 0; k < stats.splat_levels && k < 8; ++k) splatted += stats.splat_level_fragments[k];
    if (std::getenv("SUBSPLAT_REPLAY_DEBUG"))
      std::printf("  render %d: %.0f ms (GPU: buffers %.0f, splatting %.0f, shading %.0f), progress %.3f\n",
                  r.renders + 1, stats.frame_ms, stats.stage_ms[SS_STAGE_BUFFERS], stats.stage_ms[SS_STAGE_SPLATTING],
                  stats.stage_ms[SS_STAGE_SHADING], stats.splatting_progress);
    if (std::getenv("SUBSPLAT_REPLAY_DEBUG") && settings.method == SS_METHOD_PRECOMPUTED) {
      std::printf("  precomputed in %.0f ms (reused %d), relit in %.0f ms, %.0f MiB\n", stats.precompute_ms,
                  stats.transport_reused, stats.relight_ms, double(stats.precomputed_bytes) / 1048576.0);
      SsPrecomputedObject objects[64];
      uint32_t count = 0;
      if (ssGetPrecomputedObjects(context, objects, 64, &count) == SS_OK)
        for (uint32_t i = 0; i < count && i < 64; ++i)
          std::printf("    object %u: %u vertices, %llu texels of %.4g units, local range %.4g units, %llu factors, "
                      "%.0f MiB, %d charts (%d islands of its UV map, %d refused)\n",
                      objects[i].object_id, objects[i].vertices, (unsigned long long)objects[i].texels,
                      objects[i].texel_size, objects[i].local_range, (unsigned long long)objects[i].factors,
                      double(objects[i].bytes) / 1048576.0, objects[i].charts, objects[i].uv_charts,
                      objects[i].uv_islands_refused);
    }
    if (r.renders == 0) r.firstMs = stats.frame_ms;
    ++r.renders;
    r.longestMs = std::max(r.longestMs, stats.frame_ms);
    r.totalMs += stats.frame_ms;
    r.mostSplatFragments = std::max(r.mostSplatFragments, splatted);
    if (stats.splatting_complete || budget <= 0.0) break;
    if (r.renders >= 100000) throw Failure{label + ": the budgeted render did not complete in 100000 renders"};
  }
  double totalMs = r.totalMs;
  check(ssGetPass(context, SS_PASS_EXITANCE, width, height, image.exitance.data()), "exitance pass of " + label);
  check(ssGetStats(context, &stats), "stats of " + label);
  stats.frame_ms = totalMs;
  return image;
}

uint64_t totalFragments(const SsStats& stats) {
  uint64_t total = 0;
  for (uint64_t f : stats.fragment_invocations) total += f;
  return total;
}

struct SceneResults {
  std::string name;
  int width = 0, height = 0;
  std::vector<Result> results;
};

// Every entry `warmup` times uncounted, then `runs` times, round-robin, then REFERENCE once for the errors.
SceneResults measure(SsContext context, const Options& options, const std::string& path) {
  SceneResults scene;
  scene.name = baseName(path);
  int32_t savedWidth = 0, savedHeight = 0;
  check(ssLoadScene(context, path.c_str(), &savedWidth, &savedHeight), "loading " + path);
  scene.width = options.width > 0 ? options.width : savedWidth;
  scene.height = options.height > 0 ? options.height : savedHeight;
  if (scene.width <= 0 || scene.height <= 0) throw Failure{path + " holds no frame size: give --size"};
  SsSettings saved{};
  check(ssGetSettings(context, &saved), "ssGetSettings");
  std::string stem = options.images + "/" + scene.name + "_";

  scene.results.resize(options.methods.size());
  std::vector<Image> images(options.methods.size());
  for (int run = -options.warmup; run < options.runs; ++run) {
    for (size_t v = 0; v < options.methods.size(); ++v) {
      const Variant& entry = options.methods[v];
      SsStats stats{};
      BudgetRun budgetRun;
      Image image = render(context, settingsFor(saved, options, entry), scene.width, scene.height, entry.label, stats,
                           options.budget, &budgetRun);
      if (run < 0) continue;  // a warm-up frame
      if (run == 0) images[v] = std::move(image);
      scene.results[v].variant = entry;
      scene.results[v].runs.push_back(stats);
      if (options.budget > 0.0) scene.results[v].budgetRuns.push_back(budgetRun);
      std::printf("%s %s run %d: %.0f ms\n", scene.name.c_str(), entry.label.c_str(), run + 1, stats.frame_ms);
      if (options.budget > 0.0)
        std::printf("  budget %.0fM: %d renders, first %.0f ms, longest %.0f ms, most splatting fragments %.1fM\n",
                    options.budget, budgetRun.renders, budgetRun.firstMs, budgetRun.longestMs,
                    double(budgetRun.mostSplatFragments) / 1e6);
      std::fflush(stdout);
    }
  }
  Image reference;
  if (options.reference) {
    SsStats stats{};
    reference = render(context, settingsFor(saved, options, variant(SS_METHOD_REFERENCE)), scene.width, scene.height,
                       "REFERENCE", stats);
    std::printf("%s REFERENCE: %.0f ms, %llu samples\n", scene.name.c_str(), stats.frame_ms,
                static_cast<unsigned long long>(stats.splat_count));
    if (!options.images.empty()) writeImages(stem + "REFERENCE", reference);
  }
  for (size_t v = 0; v < scene.results.size(); ++v) {
    Result& result = scene.results[v];
    std::vector<double> ms;
    for (const SsStats& st : result.runs) ms.push_back(st.frame_ms);
    std::sort(ms.begin(), ms.end());
    size_t n = ms.size();
    result.medianMs = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    result.fastest = *std::min_element(result.runs.begin(), result.runs.end(),
                                       [](const SsStats& a, const SsStats& b) { return a.frame_ms < b.frame_ms; });
    if (options.reference) {
      result.errors = compare(images[v], reference);
      result.hasErrors = true;
    }
    if (!options.images.empty()) writeImages(stem + result.variant.label, images[v]);
  }
  return scene;
}

void printTable(const SceneResults& scene) {
  const Result* base = nullptr;
  for (const Result& r : scene.results)
    if (r.variant.method == SS_METHOD_BRUTE && !base) base = &r;
  std::printf("\n%s (%dx%d)\n%-12s %6s %10s %8s %10s %8s %9s  %s\n", scene.name.c_str(), scene.width, scene.height,
              "method", "levels", "median ms", "speed-up", "fragments", "ratio", "rel RMSE",
              "splatting ms: levels | accumulation | selection");
  for (const Result& r : scene.results) {
    const SsStats& st = r.fastest;
    std::string levels = std::to_string(st.levels) + "/" + std::to_string(st.splat_levels);
    std::string perLevel;
    for (int k = 0; k < st.splat_levels; ++k)
      perLevel += (k ? " " : "") + std::to_string(int(st.splat_level_ms[k] + 0.5));
    perLevel += " | " + std::to_string(int(st.accumulation_ms + 0.5));
    perLevel += " | " + std::to_string(int(st.selection_ms + 0.5));
    char rmse[32] = "-";
    if (r.hasErrors) std::snprintf(rmse, sizeof rmse, "%.5f", r.errors.radiance);
    double speedUp = base ? base->medianMs / r.medianMs : 0.0;
    // A driver's counts or times that are not counts or times (stage_profiler.h) show as "-".
    char fragments[32] = "-", ratio[32] = "-";
    if (st.statistics_available) std::snprintf(fragments, sizeof fragments, "%.0fM", double(totalFragments(st)) / 1e6);
    if (st.statistics_available && base && base->fastest.statistics_available)
      std::snprintf(ratio, sizeof ratio, "%.2fx",
                    double(totalFragments(base->fastest)) / double(std::max<uint64_t>(totalFragments(st), 1)));
    if (!st.timers_available) perLevel = "-";
    std::printf("%-12s %6s %10.0f %7.2fx %10s %8s %9s  %s\n", r.variant.label.c_str(), levels.c_str(), r.medianMs,
                speedUp, fragments, ratio, rmse, perLevel.c_str());
  }
}

template <typename T, typename F>
void jsonList(std::ostream& out, int count, F&& value) {
  out << "[";
  for (int i = 0; i < count; ++i) out << (i ? ", " : "") << T(value(i));
  out << "]";
}

void writeJson(std::ostream& json, const SceneResults& scene) {
  json << "{\"scene\": \"" << jsonEscape(scene.name) << "\", \"width\": " << scene.width
       << ", \"height\": " << scene.height << ", \"methods\": [";
  for (size_t v = 0; v < scene.results.size(); ++v) {
    const Result& r = scene.results[v];
    const SsStats& st = r.fastest;
    json << (v ? ", " : "") << "{\"method\": \"" << jsonEscape(r.variant.label) << "\", \"median_frame_ms\": "
         << r.medianMs << ", \"frame_ms\": ";
    jsonList<double>(json, int(r.runs.size()), [&](int i) { return r.runs[size_t(i)].frame_ms; });
    json << ", \"light_views\": " << st.light_views << ", \"levels\": " << st.levels << ", \"splat_levels\": " << st.splat_levels
         << ", \"irradiance_resolution\": " << st.irradiance_resolution
         << ", \"texels_per_range\": " << st.texels_per_range
         << ", \"timers_available\": " << (st.timers_available ? "true" : "false")
         << ", \"statistics_available\": " << (st.statistics_available ? "true" : "false") << ", \"stage_ms\": {";
    for (int k = 0; k < SS_STAGE_COUNT; ++k) json << (k ? ", " : "") << "\"" << kStageNames[k] << "\": " << st.stage_ms[k];
    json << "}, \"fragment_invocations\": {";
    for (int k = 0; k < SS_STAGE_COUNT; ++k) json << "\"" << kStageNames[k] << "\": " << st.fragment_invocations[k] << ", ";
    json << "\"total\": " << totalFragments(st) << "}, \"splat_level_ms\": ";
    jsonList<double>(json, st.splat_levels, [&](int k) { return st.splat_level_ms[k]; });
    json << ", \"splat_level_fragments\": ";
    jsonList<uint64_t>(json, st.splat_levels, [&](int k) { return st.splat_level_fragments[k]; });
    json << ", \"accumulation_ms\": " << st.accumulation_ms
         << ", \"accumulation_fragments\": " << st.accumulation_fragments << ", \"selection_ms\": " << st.selection_ms
         << ", \"splat_count\": " << st.splat_count
         << ", \"precompute_ms\": " << st.precompute_ms << ", \"transport_reused\": " << st.transport_reused
         << ", \"relight_ms\": " << st.relight_ms << ", \"precomputed_bytes\": " << st.precomputed_bytes;
    if (!r.budgetRuns.empty()) {
      json << ", \"budget_runs\": [";
      for (size_t i = 0; i < r.budgetRuns.size(); ++i) {
        const BudgetRun& b = r.budgetRuns[i];
        json << (i ? ", " : "") << "{\"renders\": " << b.renders << ", \"first_ms\": " << b.firstMs
             << ", \"longest_ms\": " << b.longestMs << ", \"total_ms\": " << b.totalMs
             << ", \"most_splat_fragments\": " << b.mostSplatFragments << "}";
      }
      json << "]";
    }
    if (r.hasErrors)
      json << ", \"relative_rmse\": " << r.errors.radiance << ", \"exitance_relative_rmse\": " << r.errors.exitance
           << ", \"compared_pixels\": " << r.errors.pixels;
    json << "}";
  }
  json << "]}";
}

}  // namespace

int main(int argc, char** argv) {
  Options options = parse(argc, argv);
  try {
    subsplat::testing::EglContext gl;
    SsContext context = nullptr;
    check(ssNewContext(&context), "ssNewContext");
    std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    std::printf("OpenGL renderer: %s; CPU: %s\n", renderer.c_str(), cpuName().c_str());
    std::ostringstream json;
    json << "{\"renderer\": \"" << jsonEscape(renderer) << "\", \"cpu\": \"" << jsonEscape(cpuName())
         << "\", \"api_version\": " << ssGetApiVersion() << ", \"runs\": " << options.runs << ", \"scenes\": [";
    for (size_t s = 0; s < options.scenes.size(); ++s) {
      SceneResults scene = measure(context, options, options.scenes[s]);
      printTable(scene);
      json << (s ? ", " : "");
      writeJson(json, scene);
    }
    json << "]}\n";
    check(ssReleaseContext(context), "ssReleaseContext");
    if (!options.json.empty()) {
      std::ofstream out(options.json);
      out << json.str();
      if (!out) throw Failure{"cannot write " + options.json};
    }
    return 0;
  } catch (const Failure& f) {
    std::fprintf(stderr, "subsplat_replay: %s\n", f.message.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "subsplat_replay: %s\n", e.what());
  }
  return 1;
}
