// subsplat_tables: writes the transport tables (native/src/transport/profile_table.h) and checks
// their half-space totals against Chandrasekhar's H-function (docs/TRANSPORT.md).
//
//   subsplat_tables [--small | --half-space] [--paths N] [--seed S] [--threads T] [--check] OUTPUT
//   subsplat_tables --slab-table [--threads T] OUTPUT
//   subsplat_tables --normal-incidence-albedo OUTPUT
//   subsplat_tables --hfunction ALBEDO
//   subsplat_tables --slab ALBEDO THICKNESS MU0 [PATHS]
//   subsplat_tables --dipole
//
// --small: the table the unit test regenerates; --half-space: the table the TABULATED profile model
// reads (native/src/transport/data/half_space_profiles.txt); --check: print, per albedo, the half-space
// reflectance against 1 - sqrt(1 - a) H(mu0) and each slab's against adding-doubling, in
// standard errors, and the once-scattered parts against their closed forms.
// --slab-table: the adding-doubling table of thin slabs the TABULATED model reads
// (native/src/transport/data/slab_table.txt; transport/slab_table.h).
// --normal-incidence-albedo: the nodes of R(1) = 1 - sqrt(1 - a) H(1) the library interpolates
// (native/src/transport/data/normal_incidence_albedo.txt; material/transport_model.h).
// --hfunction: print mu, H(mu) and the half-space albedo R(mu) for mu = 0, 0.05, ..., 1.
// --slab: a slab's reflectance and transmittance by adding-doubling and by the Monte Carlo
// (PATHS, default 1e6), side by side. --dipole: the classical dipole's total reflectance at
// eta = 1 beside the exact half-space albedo, for the table's albedos.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

#include "material/dipole.h"
#include "material/transport_model.h"
#include "transport/adding_doubling.h"
#include "transport/hfunction.h"
#include "transport/profile_table.h"
#include "transport/slab_table.h"

using namespace subsplat;

namespace {

int usage() {
  std::fprintf(stderr, "usage: subsplat_tables [--small | --half-space] [--paths N] [--seed S] [--threads T] [--check] OUTPUT\n"
                       "       subsplat_tables --slab-table [--threads T] OUTPUT\n"
                       "       subsplat_tables --normal-incidence-albedo OUTPUT\n"
                       "       subsplat_tables --hfunction ALBEDO\n"
                       "       subsplat_tables --slab ALBEDO THICKNESS MU0 [PATHS]\n"
                       "       subsplat_tables --dipole\n");
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
  std::printf("# R, T (with the unscattered T_unscat), A: the table. R exact, T exact: 1 - sqrt(1 - a) H(mu0) for the\n"
              "# half-space, adding-doubling (adding_doubling.h) for a slab. sig: (table - exact) / standard error,\n"
              "# for the once-scattered R1 and T1 (closed form), R and T; '-': nothing counted, or nothing to compare.\n");
  std::printf("%8s %8s %10s %10s %10s %9s %7s %7s %10s %10s %7s %7s\n", "albedo", "tau", "R", "T", "T_unscat", "A",
              "R1 sig", "T1 sig", "R exact", "T exact", "R sig", "T sig");
  for (size_t i = 0; i < spec.albedos.size(); ++i)
    for (size_t j = 0; j < spec.thicknesses.size(); ++j) {
      const SlabTallies& t = table.at(i, j);
      double a = spec.albedos[i], tau = spec.thicknesses[j];
      double r1, t1;
      singleScattering(a, tau, spec.mu0, r1, t1);
      // In standard errors; '-' where the table counted nothing (no error to measure in).
      auto sigmas = [&](uint64_t count, double exact) {
        char text[32] = "      -";
        if (count > 0 && count < t.settings.paths && !std::isnan(exact))
          std::snprintf(text, sizeof text, "%7.2f", (t.fraction(count) - exact) / t.standardError(count));
        return std::string(text);
      };
      double rExact = NAN, tExact = NAN;  // tExact: scattered transmission
      if (std::isinf(tau) && a > 0.0) {
        rExact = halfSpaceAlbedo(HFunction(a), spec.mu0);
        tExact = 0.0;
      } else if (!std::isinf(tau)) {
        SlabSolution exact = solveSlabByAddingDoubling(a, tau, spec.mu0);
        rExact = exact.reflectance;
        tExact = exact.scatteredTransmittance;
      }
      std::printf("%8.4f %8.3f %10.6f %10.6f %10.6f %9.6f %s %s %10.6f %10.6f %s %s\n", a, tau, t.reflectance(),
                  t.transmittance(), t.unscattered, t.absorptance(), sigmas(t.reflectedOnce, r1).c_str(),
                  sigmas(t.transmittedOnce, t1).c_str(), rExact, tExact + t.unscattered,
                  sigmas(t.reflected, rExact).c_str(), sigmas(t.transmitted, tExact).c_str());
    }
}

// The classical dipole's total (Jensen et al. 2001, at eta = 1) beside the exact half-space albedo
// under a beam at 1 and 0.5 and under diffuse light, 2 int_0^1 mu R(mu) dmu.
int compareDipole() {
  MuQuadrature q = gaussLegendreInSqrtMu(200);
  std::printf("# R(mu0): the exact half-space albedo; R(1) multiple: R(1) less its once-scattered part (what a\n"
              "# dipole models); dipole: Rd_total of Jensen et al. 2001 at eta = 1 (dipoleTotalReflectance).\n");
  std::printf("%8s %10s %10s %10s %10s %10s %10s %10s\n", "albedo", "R(1)", "R(0.5)", "R diffuse", "R(1) mult", "dipole",
              "dip/R(1)", "dip/mult");
  for (double a : {0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.97, 0.98, 0.99, 0.995, 0.998, 0.999}) {
    HFunction h(a);
    double diffuse = 0.0;
    for (size_t i = 0; i < q.mu.size(); ++i) diffuse += 2.0 * q.weight[i] * q.mu[i] * halfSpaceAlbedo(h, q.mu[i]);
    double dipole = dipoleTotalReflectance(a, 1.0);
    double r1 = halfSpaceAlbedo(h, 1.0), multiple = r1 - halfSpaceSingleScatteringAlbedo(a, 1.0);
    std::printf("%8.3f %10.6f %10.6f %10.6f %10.6f %10.6f %10.4f %10.4f\n", a, r1, halfSpaceAlbedo(h, 0.5), diffuse, multiple,
                dipole, dipole / r1, dipole / multiple);
  }
  return 0;
}

// A slab by adding-doubling and by the Monte Carlo (a beam at mu0), side by side.
int compareSlab(double a, double tau, double mu0, uint64_t paths) {
  SlabSolution exact = solveSlabByAddingDoubling(a, tau, mu0);
  SlabSettings settings;
  settings.albedo = a;
  settings.thickness = tau;
  settings.mu0 = mu0;
  settings.paths = paths;
  SlabTallies t = simulateSlab(settings);
  std::printf("adding-doubling: R %.9f  T scattered %.9f  T unscattered %.9f  R + T %.12f\n"
              "                 diffuse light: R %.9f  T %.9f\n"
              "Monte Carlo (%llu paths): R %.6f +- %.6f (%.2f sigma)  T scattered %.6f +- %.6f (%.2f sigma)\n",
              exact.reflectance, exact.scatteredTransmittance, exact.unscatteredTransmittance,
              exact.reflectance + exact.scatteredTransmittance + exact.unscatteredTransmittance, exact.diffuseReflectance,
              exact.diffuseTransmittance, static_cast<unsigned long long>(paths), t.reflectance(),
              t.standardError(t.reflected), (t.reflectance() - exact.reflectance) / t.standardError(t.reflected),
              t.scatteredTransmittance(), t.standardError(t.transmitted),
              (t.scatteredTransmittance() - exact.scatteredTransmittance) / t.standardError(t.transmitted));
  return 0;
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
      if (arg == "--dipole" && argc == 2) {
        return compareDipole();
      } else if (arg == "--slab" && argc >= 5 && argc <= 6) {
        return compareSlab(std::strtod(argv[2], nullptr), std::strtod(argv[3], nullptr), std::strtod(argv[4], nullptr),
                           argc == 6 ? std::strtoull(argv[5], nullptr, 10) : 1000000);
      } else if (arg == "--hfunction" && more && argc == 3) {
        HFunction h(std::strtod(argv[++i], nullptr));
        for (int k = 0; k <= 20; ++k)
          std::printf("%.2f %.17g %.17g\n", k / 20.0, h(k / 20.0), halfSpaceAlbedo(h, k / 20.0));
        return 0;
      } else if (arg == "--normal-incidence-albedo" && argc == 3) {
        std::string text = writeNormalIncidenceAlbedoNodes(solveNormalIncidenceAlbedoNodes());
        std::ofstream out(argv[2], std::ios::binary);
        out << text;
        if (!out) throw std::runtime_error(std::string("cannot write ") + argv[2]);
        return 0;
      } else if (arg == "--small") {
        spec = smallProfileTableSpec();
      } else if (arg == "--slab-table" && argc >= 3 && argc <= 5) {
        int slabThreads = 1;
        const char* path = nullptr;
        for (int j = 2; j < argc; ++j) {
          std::string a = argv[j];
          if (a == "--threads" && j + 1 < argc)
            slabThreads = std::atoi(argv[++j]);
          else
            path = argv[j];
        }
        if (!path) return usage();
        auto start = std::chrono::steady_clock::now();
        std::string text = writeSlabTable(makeSlabTable(slabThreads));
        std::ofstream out(path, std::ios::binary);
        out << text;
        if (!out) throw std::runtime_error(std::string("cannot write ") + path);
        std::fprintf(stderr, "subsplat_tables: slab table in %.1f s (%d threads), %zu bytes to %s\n",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), slabThreads,
                     text.size(), path);
        return 0;
      } else if (arg == "--half-space") {
        spec = halfSpaceProfileTableSpec();
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
