#include "transport/slab_table.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "transport/adding_doubling.h"
#include "transport/profile_table.h"
#include "transport/table_text.h"
#include "util/error.h"
#include "util/parallel.h"

namespace subsplat {

namespace {

const char kMagic[] = "subsplat-slab-table";
const int kVersion = 1;
constexpr int kCosines = 8;
constexpr int kThicknesses = 32;  // besides 0

// Radiance at mu from values at the solver's nodes, linear in sqrt(mu) (beyond the last node:
// the last segment's line, to mu = 1).
double atCosine(const std::vector<double>& mu, const std::vector<double>& value, double at) {
  double t = std::sqrt(at);
  size_t n = mu.size();
  size_t k = 1;
  while (k + 1 < n && std::sqrt(mu[k]) < t) ++k;
  double t0 = std::sqrt(mu[k - 1]), t1 = std::sqrt(mu[k]);
  double f = (t - t0) / (t1 - t0);
  if (t < t0) f = 0.0;  // below the first node: its value (the radiance is finite at mu = 0)
  return std::max(value[k - 1] + f * (value[k] - value[k - 1]), 0.0);
}

}  // namespace

SlabTable slabTableGrid() {
  SlabTable t;
  t.albedos = halfSpaceProfileTableSpec().albedos;
  t.thicknesses.push_back(0.0);
  for (int k = 0; k < kThicknesses; ++k) t.thicknesses.push_back(std::exp2(-4.0 + 12.0 * k / (kThicknesses - 1)));
  for (int j = 1; j <= kCosines; ++j) t.cosines.push_back(double(j * j) / (kCosines * kCosines));
  return t;
}

SlabTable makeSlabTable(int threads) {
  SlabTable t = slabTableGrid();
  size_t na = t.albedos.size(), nt = t.thicknesses.size(), nc = t.cosines.size();
  t.reflectance.assign(na * nt * nc, 0.0f);
  t.transmitted.assign(na * nt * nc * nc, 0.0f);
  auto solve = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      size_t a = i / (nt * nc), k = i / nc % nt, m0 = i % nc;
      if (t.thicknesses[k] == 0.0) continue;  // nothing scatters in no thickness
      SlabSolution s = solveSlabByAddingDoubling(t.albedos[a], t.thicknesses[k], t.cosines[m0]);
      t.reflectance[t.index(a, k, m0)] = float(s.reflectance);
      for (size_t m = 0; m < nc; ++m)
        t.transmitted[t.index(a, k, m0) * nc + m] = float(atCosine(s.mu, s.transmittedRadiance, t.cosines[m]));
    }
  };
  if (threads <= 1)
    solve(0, na * nt * nc);
  else
    parallelFor(na * nt * nc, 8, solve, nullptr, 0.0, 1.0);
  return t;
}

std::string writeSlabTable(const SlabTable& t) {
  std::ostringstream out;
  out << kMagic << ' ' << kVersion << '\n'
      << "# Index-matched (eta = 1), isotropically scattering slabs under a collimated beam of unit\n"
         "# irradiance at cosine mu0, by adding-doubling (native/src/transport/adding_doubling.h, 32 nodes;\n"
         "# docs/TRANSPORT.md). Thickness in mean free paths. Per (albedo, thickness, mu0): the fraction\n"
         "# reflected after scattering, then the radiance transmitted after scattering at each cosine mu,\n"
         "# per unit irradiance (1/sr). Written by subsplat_tables --slab-table.\n";
  auto list = [&](const char* name, const std::vector<double>& v) {
    out << name << ' ' << v.size();
    for (double x : v) out << ' ' << formatReal(x);
    out << '\n';
  };
  list("albedos", t.albedos);
  list("thicknesses", t.thicknesses);
  list("cosines", t.cosines);
  size_t nc = t.cosines.size();
  for (size_t a = 0; a < t.albedos.size(); ++a)
    for (size_t k = 0; k < t.thicknesses.size(); ++k)
      for (size_t m0 = 0; m0 < nc; ++m0) {
        size_t i = t.index(a, k, m0);
        out << formatReal(t.reflectance[i], 6);
        for (size_t m = 0; m < nc; ++m) out << ' ' << formatReal(t.transmitted[i * nc + m], 6);
        out << '\n';
      }
  out << "end\n";
  return out.str();
}

SlabTable readSlabTable(const std::string& text) {
  TableWords in(text, "slab table");
  in.expect(kMagic);
  if (in.count() != uint64_t(kVersion)) in.bad("unknown version");
  SlabTable t;
  t.albedos = in.list("albedos", 1000);
  t.thicknesses = in.list("thicknesses", 1000);
  t.cosines = in.list("cosines", 1000);
  if (t.albedos.size() < 2 || t.thicknesses.size() < 3 || t.cosines.size() < 2)
    in.bad("too few albedos, thicknesses or cosines");
  if (!(t.albedos.front() > 0.0 && t.albedos.back() <= 1.0 && t.thicknesses.front() >= 0.0 && t.cosines.front() > 0.0 &&
        t.cosines.back() <= 1.0))
    in.bad("albedos and cosines must lie in (0, 1], thicknesses be at least 0");
  size_t nc = t.cosines.size(), entries = t.albedos.size() * t.thicknesses.size() * nc;
  t.reflectance.resize(entries);
  t.transmitted.resize(entries * nc);
  auto value = [&in] {  // reflectance and radiance: finite and not negative
    double x = in.real();
    if (x < 0.0) in.bad("negative value " + formatReal(x));
    return float(x);
  };
  for (size_t i = 0; i < entries; ++i) {
    t.reflectance[i] = value();
    for (size_t m = 0; m < nc; ++m) t.transmitted[i * nc + m] = value();
  }
  in.expect("end");
  for (size_t i = 1; i < t.albedos.size(); ++i) require(t.albedos[i] > t.albedos[i - 1], "slab table: albedos must increase");
  for (size_t i = 1; i < t.thicknesses.size(); ++i)
    require(t.thicknesses[i] > t.thicknesses[i - 1], "slab table: thicknesses must increase");
  for (size_t i = 1; i < nc; ++i) require(t.cosines[i] > t.cosines[i - 1], "slab table: cosines must increase");
  return t;
}

}  // namespace subsplat
