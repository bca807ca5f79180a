// The adding-doubling method (van de Hulst 1980; Prahl 1995) for an index-matched (eta = 1),
// isotropically scattering slab: a deterministic answer, independent of the Monte Carlo, for
// the slab's reflectance and transmittance at every thickness (issue 19: thin-slab transmission;
// docs/TRANSPORT.md). Same units and conventions as slab_monte_carlo.h.
//
// Directions are the nodes of Gauss-Legendre in sqrt(mu) (hfunction.h) plus the beam's mu0 as an
// extra node of weight zero. A layer's reflection and transmission are matrices of flux (power per
// unit area) from each incoming node to each outgoing one; a layer of optical thickness 1e-9 or
// less starts as its exact single scattering, and layers are doubled, R' = R + T R (I - R R)^-1 T,
// T' = T (I - R R)^-1 T, until the slab is as thick as asked.
#pragma once

#include <vector>

namespace subsplat {

struct SlabSolution {
  double reflectance = 0.0;              // fraction of the beam's power reflected
  double scatteredTransmittance = 0.0;   // transmitted after scattering
  double unscatteredTransmittance = 0.0; // exp(-tau / mu0)
  double diffuseReflectance = 0.0;       // the same under uniform light from the whole hemisphere
  double diffuseTransmittance = 0.0;     // (scattered and unscattered)
  // Radiance leaving at each node mu per unit irradiance of the beam, reflected and transmitted
  // (scattered light only).
  std::vector<double> mu, reflectedRadiance, transmittedRadiance;
};

// albedo in [0, 1], thickness finite and > 0, mu0 in (0, 1]; nodes in sqrt(mu) (32: totals to
// about 1e-7). Throws Error (SS_INVALID_ARGUMENT) otherwise.
SlabSolution solveSlabByAddingDoubling(double albedo, double thickness, double mu0, int nodes = 32);

}  // namespace subsplat
