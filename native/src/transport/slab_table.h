// Reflectance and transmitted radiance of index-matched (eta = 1), isotropically scattering slabs
// over albedo, thickness and the cosine of incidence, by adding-doubling (adding_doubling.h): what
// the TABULATED profile model reads for thin parts (material/transport_model.h; docs/TRANSPORT.md,
// "The TABULATED model"). Units and conventions as slab_monte_carlo.h: thickness in mean free
// paths, a collimated beam at mu0 of unit irradiance on the surface.
//
// Written by `subsplat_tables --slab-table OUTPUT` (deterministic: the same program gives the same
// bytes), committed as native/src/transport/data/slab_table.txt and embedded into the library.
#pragma once

#include <string>
#include <vector>

namespace subsplat {

struct SlabTable {
  std::vector<double> albedos;      // the half-space table's (profile_table.h)
  std::vector<double> thicknesses;  // 0, then 32 geometric from 1/16 to 256 mean free paths
  std::vector<double> cosines;      // mu0 and mu: (j / n)^2, j = 1 .. n (uniform in sqrt(mu))
  // [albedo][thickness][mu0]: the fraction of the beam reflected (scattered light).
  std::vector<float> reflectance;
  // [albedo][thickness][mu0][mu]: radiance leaving the far face at mu after scattering, per unit
  // irradiance of the beam, in 1/sr (the unscattered beam is not in it).
  std::vector<float> transmitted;

  size_t index(size_t a, size_t t, size_t m0) const {
    return (a * thicknesses.size() + t) * cosines.size() + m0;
  }
};

// The grids: 25 albedos, 33 thicknesses, 8 cosines.
SlabTable slabTableGrid();
// Solves every entry (6600 solves of 32 nodes; about 40 s of CPU, spread over `threads`).
SlabTable makeSlabTable(int threads = 1);
// Text: every value to 6 significant digits (std::to_chars, the C locale's format).
std::string writeSlabTable(const SlabTable& table);
// Reads what writeSlabTable wrote; throws Error (SS_INVALID_ARGUMENT) on anything else.
SlabTable readSlabTable(const std::string& text);

}  // namespace subsplat
