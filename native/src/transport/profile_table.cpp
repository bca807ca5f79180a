#include "transport/profile_table.h"

#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "transport/table_text.h"
#include "util/error.h"

namespace subsplat {

namespace {

const char kMagic[] = "subsplat-transport-table";
const int kVersion = 1;

void writeList(std::ostringstream& out, const char* name, const std::vector<double>& v) {
  out << name << ' ' << v.size();
  for (double x : v) out << ' ' << formatReal(x);
  out << '\n';
}

void writeCounts(std::ostringstream& out, const char* name, const std::vector<uint64_t>& v) {
  out << name;
  for (uint64_t c : v) out << ' ' << c;
  out << '\n';
}

}  // namespace

std::vector<double> geometricRadiusEdges(double first, double last, int bins) {
  require(first > 0.0 && last > first && bins >= 1, "geometric radius edges: 0 < first < last, bins >= 1");
  std::vector<double> edges = {0.0};
  for (int i = 0; i <= bins; ++i) edges.push_back(first * std::pow(last / first, static_cast<double>(i) / bins));
  return edges;
}

ProfileTableSpec defaultProfileTableSpec() {
  ProfileTableSpec spec;
  spec.albedos = {0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.97, 0.98, 0.99, 0.995, 0.998, 0.999};
  spec.thicknesses = {std::numeric_limits<double>::infinity(), 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
  spec.radiusEdges = geometricRadiusEdges(0.01, 200.0, 48);
  spec.paths = 1000000;
  return spec;
}

ProfileTableSpec halfSpaceProfileTableSpec() {
  ProfileTableSpec spec;
  spec.albedos = {0.05,  0.1,   0.2,   0.3,   0.4,   0.5,   0.6,    0.7,    0.8,    0.85,   0.9,    0.925, 0.95,
                  0.965, 0.975, 0.985, 0.99,  0.993, 0.995, 0.997, 0.998, 0.999, 0.9995, 0.9998, 0.9999};
  spec.thicknesses = {std::numeric_limits<double>::infinity()};
  spec.radiusEdges = geometricRadiusEdges(0.005, 3000.0, 64);
  spec.paths = 1000000;
  return spec;
}

ProfileTableSpec smallProfileTableSpec() {
  ProfileTableSpec spec;
  spec.albedos = {0.5, 0.9, 0.99};
  spec.thicknesses = {std::numeric_limits<double>::infinity(), 1.0};
  spec.radiusEdges = geometricRadiusEdges(0.05, 50.0, 11);
  spec.paths = 20000;
  return spec;
}

ProfileTable makeProfileTable(const ProfileTableSpec& spec) {
  require(!spec.albedos.empty() && !spec.thicknesses.empty() && spec.radiusEdges.size() >= 2,
          "transport table: albedos, thicknesses and at least two radius edges");
  ProfileTable table;
  table.spec = spec;
  for (double a : spec.albedos)
    for (double tau : spec.thicknesses) {
      SlabSettings s;
      s.albedo = a;
      s.thickness = tau;
      s.mu0 = spec.mu0;
      s.paths = spec.paths;
      s.seed = spec.seed;
      s.radiusEdges = spec.radiusEdges;
      s.cosineBins = spec.cosineBins;
      s.threads = spec.threads;
      table.entries.push_back(simulateSlab(s));
    }
  return table;
}

std::string writeProfileTable(const ProfileTable& table) {
  const ProfileTableSpec& spec = table.spec;
  std::ostringstream out;
  out << kMagic << ' ' << kVersion << '\n';
  out << "# Radial profiles of an index-matched (eta = 1), isotropically scattering slab (thickness inf:\n"
         "# the half-space) under a pencil beam of unit power at cosine mu0, by native/src/transport/\n"
         "# slab_monte_carlo (docs/TRANSPORT.md). Lengths in mean free paths. Per entry: the exact\n"
         "# unscattered transmittance and the collided share each path stands for; the paths reflected,\n"
         "# transmitted (after scattering), absorbed and truncated, and those that left after one\n"
         "# collision; per radial bin, the paths that left through the top (reflected) and bottom face;\n"
         "# the same per exit-cosine bin (uniform in mu). A count c is the fraction collided * c / paths of\n"
         "# the incident power; the mean exitance over a radial bin [r0, r1] is that over pi (r1^2 - r0^2),\n"
         "# the mean radiance over a cosine bin [m0, m1] per unit irradiance that over pi (m1^2 - m0^2).\n";
  out << "mu0 " << formatReal(spec.mu0) << '\n' << "paths " << spec.paths << '\n' << "seed " << spec.seed << '\n';
  writeList(out, "albedos", spec.albedos);
  writeList(out, "thicknesses", spec.thicknesses);
  writeList(out, "radius-edges", spec.radiusEdges);
  out << "cosine-bins " << spec.cosineBins << '\n';
  for (const SlabTallies& t : table.entries) {
    out << "entry " << formatReal(t.settings.albedo) << ' ' << formatReal(t.settings.thickness) << " unscattered " << formatReal(t.unscattered)
        << " collided " << formatReal(t.collided) << " reflected " << t.reflected << " transmitted " << t.transmitted << " absorbed "
        << t.absorbed << " truncated " << t.truncated << " reflected-once " << t.reflectedOnce << " transmitted-once "
        << t.transmittedOnce << '\n';
    writeCounts(out, "reflected-by-radius", t.reflectedByRadius);
    writeCounts(out, "transmitted-by-radius", t.transmittedByRadius);
    writeCounts(out, "reflected-by-cosine", t.reflectedByCosine);
    writeCounts(out, "transmitted-by-cosine", t.transmittedByCosine);
  }
  out << "end\n";
  return out.str();
}

ProfileTable readProfileTable(const std::string& text) {
  TableWords in(text, "transport table");
  in.allowInfinity = true;  // the half-space's thickness
  in.expect(kMagic);
  if (in.count() != static_cast<uint64_t>(kVersion)) fail(SS_INVALID_ARGUMENT, "transport table: unknown version");
  in.expect("mu0");
  ProfileTable table;
  ProfileTableSpec& spec = table.spec;
  spec.mu0 = in.real();
  in.expect("paths");
  spec.paths = in.count();
  in.expect("seed");
  spec.seed = in.count();
  spec.albedos = in.list("albedos");
  spec.thicknesses = in.list("thicknesses");
  spec.radiusEdges = in.list("radius-edges");
  in.expect("cosine-bins");
  uint64_t cosineBins = in.count();
  require(cosineBins <= 100000, "transport table: too many cosine bins");
  spec.cosineBins = static_cast<int>(cosineBins);
  require(spec.radiusEdges.size() >= 2 && spec.paths > 0, "transport table: no bins or no paths");
  size_t bins = spec.radiusEdges.size() - 1;
  for (double a : spec.albedos)
    for (double tau : spec.thicknesses) {
      SlabTallies t;
      in.expect("entry");
      t.settings.albedo = in.real();
      t.settings.thickness = in.real();
      require(t.settings.albedo == a && t.settings.thickness == tau, "transport table: entries out of order");
      t.settings.mu0 = spec.mu0;
      t.settings.paths = spec.paths;
      t.settings.seed = spec.seed;
      t.settings.radiusEdges = spec.radiusEdges;
      t.settings.cosineBins = spec.cosineBins;
      in.expect("unscattered");
      t.unscattered = in.real();
      in.expect("collided");
      t.collided = in.real();
      in.expect("reflected");
      t.reflected = in.count();
      in.expect("transmitted");
      t.transmitted = in.count();
      in.expect("absorbed");
      t.absorbed = in.count();
      in.expect("truncated");
      t.truncated = in.count();
      in.expect("reflected-once");
      t.reflectedOnce = in.count();
      in.expect("transmitted-once");
      t.transmittedOnce = in.count();
      require(t.reflected + t.transmitted + t.absorbed + t.truncated == spec.paths, "transport table: counts do not add up");
      t.reflectedByRadius = in.counts("reflected-by-radius", bins);
      t.transmittedByRadius = in.counts("transmitted-by-radius", bins);
      t.reflectedByCosine = in.counts("reflected-by-cosine", cosineBins);
      t.transmittedByCosine = in.counts("transmitted-by-cosine", cosineBins);
      table.entries.push_back(t);
    }
  in.expect("end");
  require(in.done(), "transport table: text after the end");
  return table;
}

}  // namespace subsplat
