// The edit basis against the number of coefficients (docs/MATERIAL_EDIT.md, "The basis"; the
// paper's Figures 1 and 2 on our profiles): piecewise linear and quadratic B-splines on the fitted
// knots (ProfileBasis::fitted, on the calibration media) and on uniform knots, each projected
// profile's relative L1 error in the area measure and its energy error, over the calibration media
// and over the test profiles (the presets as precomputed and edited, random media of another seed).
//
//   subsplat_basis [--intervals 2,4,8,...] > bench/results/material_edit_basis.json
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "material/profile_basis.h"
#include "testing/edit_family.h"

using namespace subsplat;

namespace {

struct Summary {
  double meanL1 = 0.0, maxL1 = 0.0, maxEnergy = 0.0, maxTail = 0.0, meanCumulative = 0.0, maxCumulative = 0.0;
  std::string worst;
  int beyondReach = 0;  // members left out: their support is past the basis's reach
};

Summary measure(const ProfileBasis& basis, const std::vector<testing::EditFamilyMember>& family) {
  Summary s;
  size_t within = 0;
  for (const testing::EditFamilyMember& m : family) within += m.withinReach ? 1 : 0;
  for (const testing::EditFamilyMember& m : family) {
    if (!m.withinReach) {
      ++s.beyondReach;
      continue;
    }
    ScaledProfile p = m.profile.view();
    ProfileBasis::Error e = basis.error(p, basis.project(p));
    s.meanL1 += e.l1 / double(within);
    if (e.l1 > s.maxL1) s.maxL1 = e.l1, s.worst = m.name;
    s.maxEnergy = std::max(s.maxEnergy, std::abs(e.energy));
    s.maxTail = std::max(s.maxTail, e.tail);
    s.meanCumulative += e.cumulative / double(within);
    s.maxCumulative = std::max(s.maxCumulative, e.cumulative);
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> intervals = {2, 3, 4, 6, 8, 12, 16, 24, 32};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--intervals") == 0 && i + 1 < argc) {
      intervals.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) intervals.push_back(std::atoi(item.c_str()));
    } else {
      std::fprintf(stderr, "usage: subsplat_basis [--intervals 2,4,8,...]\n");
      return 2;
    }
  }
  std::vector<testing::EditFamilyMember> calibration;
  for (OwnedProfile& p : randomMediaFamily(kCalibrationSeed, kCalibrationMedia))
    calibration.push_back({"calibration", p, true, false});
  std::vector<testing::EditFamilyMember> presets = testing::presetEditFamily();
  std::vector<testing::EditFamilyMember> random = testing::randomTestFamily(64);
  // How much sigma_s' x 0.5, the edit that lengthens a profile most, lengthens each preset's
  // support (its longest channel's, as SupportedProfile cut them) under each model: what
  // TransportSplatting::kSupportGrowth must carry (docs/MATERIAL_EDIT.md, "The precomputation").
  std::map<std::string, double> supports;
  for (const testing::EditFamilyMember& m : presets) {
    const auto* cut = dynamic_cast<const SupportedProfile*>(m.profile.profile.get());
    if (cut && m.name.size() > 10 && m.name.compare(m.name.size() - 10, 10, " channel 0") == 0)
      supports[m.name.substr(0, m.name.size() - 10)] = cut->support();
  }
  std::printf("{\"reach\": %g, \"calibration_media\": %zu, \"preset_profiles\": %zu, \"test_media\": %zu,\n"
              " \"support_growth_sigma_s_half\": {",
              kEditReach, calibration.size(), presets.size(), random.size());
  const std::string half = " sigma_s' x0.5";
  bool firstGrowth = true;
  for (const auto& [name, support] : supports) {
    auto edited = supports.find(name + half);
    if (name.find(" sigma_") != std::string::npos || edited == supports.end() || !(support > 0.0)) continue;
    std::printf("%s\"%s\": %.4f", firstGrowth ? "" : ", ", name.c_str(), edited->second / support);
    firstGrowth = false;
  }
  std::printf("},\n \"rows\": [\n");
  bool first = true;
  for (int m : intervals)
    for (int degree : {1, 2})
      for (bool fittedKnots : {true, false}) {
        auto start = std::chrono::steady_clock::now();
        ProfileBasis basis = fittedKnots ? editBasis(m, degree) : ProfileBasis::uniform(kEditReach, m, degree);
        double fitMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        Summary c = measure(basis, calibration), p = measure(basis, presets), r = measure(basis, random);
        std::printf("%s  {\"intervals\": %d, \"coefficients\": %d, \"degree\": %d, \"knots\": \"%s\", \"fit_ms\": %.1f,\n",
                    first ? "" : ",\n", m, basis.size(), degree, fittedKnots ? "fitted" : "uniform", fitMs);
        first = false;
        auto row = [](const char* name, const Summary& s, bool last) {
          std::printf("   \"%s\": {\"mean_l1\": %.6g, \"max_l1\": %.6g, \"max_energy\": %.6g, \"max_tail\": %.6g, "
                      "\"mean_cumulative\": %.6g, \"max_cumulative\": %.6g, \"beyond_reach\": %d, \"worst\": \"%s\"}%s\n",
                      name, s.meanL1, s.maxL1, s.maxEnergy, s.maxTail, s.meanCumulative, s.maxCumulative,
                      s.beyondReach, s.worst.c_str(), last ? "}" : ",");
        };
        row("calibration", c, false);
        row("presets", p, false);
        row("test_media", r, true);
        std::fflush(stdout);
      }
  std::printf("]}\n");
  return 0;
}
