// subsplat_tables: writes the transport tables (native/src/transport/profile_table.h) and checks
// their half-space totals against Chandrasekhar's H-function (docs/TRANSPORT.md).
//
//   subsplat_tables [--small] [--paths N] [--seed S] [--threads T] [--check] OUTPUT
//
// --small: the table the unit test regenerates; --check: print, per albedo, the half-space
// reflectance against 1 - sqrt(1 - a) H(mu0) in standard errors, and each slab's totals.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

#include "transport/hfunction.h"
#include "transport/profile_table.h"

using namespace subsplat;

namespace {

int usage() {
  std::fprintf(stderr, "usage: subsplat_tables [--small] [--paths N] [--seed S] [--threads T] [--check] OUTPUT\n");
  return 2;
}

void check(const ProfileTable& table) {
  const ProfileTableSpec& spec = table.spec;
  std::printf("%8s %8s %10s %10s %10s %9s %10s %10s %8s\n", "albedo", "tau", "R", "T", "T_unscat", "A", "R exact",
              "R - exact", "sigmas");
  for (size_t i = 0; i < spec.albedos.size(); ++i)
    for (size_t j = 0; j < spec.thicknesses.size(); ++j) {
      const SlabTallies& t = table.at(i, j);
      std::printf("%8.4f %8.3f %10.6f %10.6f %10.6f %9.6f", spec.albedos[i], spec.thicknesses[j], t.reflectance(),
                  t.transmittance(), t.unscattered, t.absorptance());
      if (std::isinf(spec.thicknesses[j]) && spec.albedos[i] > 0.0) {
        double exact = halfSpaceAlbedo(HFunction(spec.albedos[i]), spec.mu0);
        std::printf(" %10.6f %10.2e %8.2f", exact, t.reflectance() - exact,
                    (t.reflectance() - exact) / t.standardError(t.reflected));
      }
      std::printf("\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    ProfileTableSpec spec = defaultProfileTableSpec();
    bool doCheck = false;
    const char* output = nullptr;
    uint64_t paths = 0, seed = 0;
    bool setSeed = false;
    int threads = 1;
    for (int i = 1; i < argc; ++i) {
      std::string arg = argv[i];
      bool more = i + 1 < argc;
      if (arg == "--small") {
        spec = smallProfileTableSpec();
      } else if (arg == "--check") {
        doCheck = true;
      } else if (arg == "--paths" && more) {
        paths = std::strtoull(argv[++i], nullptr, 10);
      } else if (arg == "--seed" && more) {
        seed = std::strtoull(argv[++i], nullptr, 10);
        setSeed = true;
      } else if (arg == "--threads" && more) {
        threads = std::atoi(argv[++i]);
      } else if (!arg.empty() && arg[0] != '-' && !output) {
        output = argv[i];
      } else {
        return usage();
      }
    }
    if (!output) return usage();
    if (paths) spec.paths = paths;
    if (setSeed) spec.seed = seed;
    spec.threads = threads;
    auto start = std::chrono::steady_clock::now();
    ProfileTable table = makeProfileTable(spec);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::string text = writeProfileTable(table);
    std::ofstream out(output, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error(std::string("cannot write ") + output);
    std::fprintf(stderr, "subsplat_tables: %zu entries of %llu paths in %.1f s (%d threads), %zu bytes to %s\n",
                 table.entries.size(), static_cast<unsigned long long>(spec.paths), seconds, threads, text.size(), output);
    if (doCheck) check(table);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "subsplat_tables: %s\n", e.what());
    return 1;
  }
}
