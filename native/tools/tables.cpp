// subsplat_tables: writes the transport tables (native/src/transport/profile_table.h) and checks
// their half-space totals against Chandrasekhar's H-function (docs/TRANSPORT.md).
//
//   subsplat_tables [--small] [--paths N] [--seed S] [--threads T] [--check] OUTPUT
//   subsplat_tables --hfunction ALBEDO
//
// --small: the table the unit test regenerates; --check: print, per albedo, the half-space
// reflectance against 1 - sqrt(1 - a) H(mu0) in standard errors, and each slab's totals.
// --hfunction: print mu, H(mu) and the half-space albedo R(mu) for mu = 0, 0.05, ..., 1.
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
  std::fprintf(stderr, "usage: subsplat_tables [--small] [--paths N] [--seed S] [--threads T] [--check] OUTPUT\n"
                       "       subsplat_tables --hfunction ALBEDO\n");
  return 2;
}

// Once-scattered reflectance and transmittance of a slab under a beam at mu0 (closed-form
// radiance, integrated over the exit cosine by Gauss-Legendre in sqrt(mu)).
void singleScattering(double a, double tau, double mu0, double& reflected, double& transmitted) {
  MuQuadrature q = gaussLegendreInSqrtMu(200);
  reflected = transmitted = 0.0;
  for (size_t i = 0; i < q.mu.size(); ++i) {
    double mu = q.mu[i], w = 2.0 * M_PI * q.weight[i] * mu;
    reflected += w * a * -std::expm1(-tau * (1 / mu0 + 1 / mu)) / (4 * M_PI * (mu0 + mu));
    if (!std::isinf(tau))
      transmitted += w * (std::abs(mu - mu0) < 1e-12 ? a * tau * std::exp(-tau / mu0) / (4 * M_PI * mu0 * mu0)
                                                     : a * (std::exp(-tau / mu) - std::exp(-tau / mu0)) / (4 * M_PI * (mu - mu0)));
  }
}

void check(const ProfileTable& table) {
  const ProfileTableSpec& spec = table.spec;
  std::printf("# R, T (with the unscattered T_unscat), A: the table. R exact: 1 - sqrt(1 - a) H(mu0) (half-space).\n"
              "# sigmas: (table - exact) / standard error, for R, and for the once-scattered R1 and T1 (closed form).\n");
  std::printf("%8s %8s %10s %10s %10s %9s %8s %8s %10s %10s %8s\n", "albedo", "tau", "R", "T", "T_unscat", "A",
              "R1 sig", "T1 sig", "R exact", "R - exact", "R sig");
  for (size_t i = 0; i < spec.albedos.size(); ++i)
    for (size_t j = 0; j < spec.thicknesses.size(); ++j) {
      const SlabTallies& t = table.at(i, j);
      double r1, t1;
      singleScattering(spec.albedos[i], spec.thicknesses[j], spec.mu0, r1, t1);
      // In standard errors; '-' where the table counted nothing (no error to measure in).
      auto sigmas = [&](uint64_t count, double exact) {
        char text[32] = "       -";
        if (count > 0 && count < t.settings.paths)
          std::snprintf(text, sizeof text, "%8.2f", (t.fraction(count) - exact) / t.standardError(count));
        return std::string(text);
      };
      std::printf("%8.4f %8.3f %10.6f %10.6f %10.6f %9.6f %s %s", spec.albedos[i], spec.thicknesses[j], t.reflectance(),
                  t.transmittance(), t.unscattered, t.absorptance(), sigmas(t.reflectedOnce, r1).c_str(),
                  sigmas(t.transmittedOnce, t1).c_str());
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
      if (arg == "--hfunction" && more && argc == 3) {
        HFunction h(std::strtod(argv[++i], nullptr));
        for (int k = 0; k <= 20; ++k)
          std::printf("%.2f %.17g %.17g\n", k / 20.0, h(k / 20.0), halfSpaceAlbedo(h, k / 20.0));
        return 0;
      } else if (arg == "--small") {
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
