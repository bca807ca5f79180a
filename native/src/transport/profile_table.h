// Tables of the half-space's radial reflectance profile and of slabs' transmission (and
// reflection) profiles over albedo and thickness, made by the slab Monte Carlo with a fixed seed
// (issue 19; docs/TRANSPORT.md). Lengths in mean free paths; a pencil beam of unit power at cosine
// mu0 (1: normal incidence) enters at r = 0. The program subsplat_tables (native/tools/tables.cpp)
// writes them; the build makes the full table on request (target transport_tables).
//
// The file is text, one record a line, every count an integer and every real printed with 17
// significant digits (it reads back exactly), so the same program and seed give the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "transport/slab_monte_carlo.h"

namespace subsplat {

struct ProfileTableSpec {
  std::vector<double> albedos;      // each in [0, 1]
  std::vector<double> thicknesses;  // mean free paths; infinity: the half-space
  std::vector<double> radiusEdges;  // radial bin edges, mean free paths
  int cosineBins = 10;              // exit-cosine bins, uniform in mu
  double mu0 = 1.0;                 // a collimated beam at this cosine
  uint64_t paths = 1000000;         // per (albedo, thickness)
  uint64_t seed = 1;                // the same for every entry: common random numbers across albedo
  int threads = 1;                  // does not change a count
};

// What the build makes: 18 albedos from 0.05 to 0.999, thicknesses 1/8 to 16 and the half-space,
// 48 radial bins from 0.01 to 200 (geometric, and [0, 0.01]), 1e6 paths each.
ProfileTableSpec defaultProfileTableSpec();
// What the renderer's TABULATED profile model reads (material/tabulated_profile.h): the half-space
// alone, 25 albedos from 0.05 to 0.9999 (dense towards 1, where the profile's tail grows), 64 radial
// bins from 0.005 to 3000 mean free paths (geometric, and [0, 0.005]), 1e6 paths each. Committed as
// native/src/transport/data/half_space_profiles.txt and embedded into the library.
ProfileTableSpec halfSpaceProfileTableSpec();
// What the test regenerates: 3 albedos, 2 thicknesses, 12 bins, 20000 paths.
ProfileTableSpec smallProfileTableSpec();

// 0, then `bins` edges geometric from `first` to `last`.
std::vector<double> geometricRadiusEdges(double first, double last, int bins);

struct ProfileTable {
  ProfileTableSpec spec;
  std::vector<SlabTallies> entries;  // albedo-major: entries[i * thicknesses + j]

  const SlabTallies& at(size_t albedo, size_t thickness) const {
    return entries.at(albedo * spec.thicknesses.size() + thickness);
  }
};

ProfileTable makeProfileTable(const ProfileTableSpec& spec);
std::string writeProfileTable(const ProfileTable& table);
// Reads what writeProfileTable wrote; throws Error (SS_INVALID_ARGUMENT) on anything else.
ProfileTable readProfileTable(const std::string& text);

}  // namespace subsplat
