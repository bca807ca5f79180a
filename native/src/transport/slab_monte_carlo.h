// A deterministic Monte Carlo of light in an index-matched (eta = 1), isotropically scattering
// slab: the repo's own one-dimensional (and, with radial tallies, three-dimensional) truth for
// thin-slab transmission and half-space profiles (issue 19; docs/TRANSPORT.md).
//
// Units and conventions: lengths in mean free paths (the slab's optical thickness tau; radii r
// from the point where the beam enters), cosines against the surface normal, the beam arriving
// on the top face z = 0 and travelling into z > 0; thickness infinity is the half-space.
// Results are fractions of the incident power. Analog transport: each simulated path carries the
// same weight, collides, is absorbed with probability 1 - a at each collision and otherwise
// scatters isotropically, until it leaves through a face; so every tally is a count of paths.
//
// The unscattered transmission is not simulated but computed exactly: exp(-tau / mu0) for a
// collimated beam, 2 E_3(tau) for diffuse light. Every simulated path is made to collide at least
// once (its first free flight drawn within the slab) and stands for the collided power
// 1 - unscattered. So, in the tallies' own accounting, reflected + transmitted + absorbed +
// truncated counts equal the number of paths exactly, and R + T + A = 1 to rounding.
//
// Determinism: each path draws from its own xoshiro256** generator seeded by splitmix64 from
// (seed, path index), and tallies are integer counts, so results do not depend on the number of
// threads and are identical on every machine whose libm rounds log, sin, cos as this one does.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace subsplat {

enum class SlabIncidence {
  Collimated,  // a parallel beam at cosine mu0
  Diffuse,     // uniform radiance from the whole upper hemisphere (cosine-weighted incidence)
};

struct SlabSettings {
  double albedo = 0.8;                                         // single-scattering albedo a, [0, 1]
  double thickness = std::numeric_limits<double>::infinity();  // tau, mean free paths, > 0
  // Diffuse light draws the incidence cosine by rejection (kept with probability
  // 1 - e^{-tau/mu0}): slabs thinner than about 1e-3 mfp take hundreds of draws a path.
  SlabIncidence incidence = SlabIncidence::Collimated;
  double mu0 = 1.0;                                            // collimated: cosine of incidence, (0, 1]
  uint64_t paths = 100000;
  uint64_t seed = 1;
  int cosineBins = 0;                // exit-cosine bins, uniform in mu over [0, 1]; 0: none
  std::vector<double> radiusEdges;   // radial bin edges in mean free paths, increasing, >= 0; empty: none
  uint64_t maxCollisions = 1000000;  // a path still inside after this many collisions is truncated
  int threads = 1;
};

struct SlabTallies {
  SlabSettings settings;
  double unscattered = 0.0;  // exact unscattered transmittance, fraction of the incident power
  double collided = 0.0;     // 1 - unscattered: the power the simulated paths stand for
  uint64_t reflected = 0, transmitted = 0, absorbed = 0, truncated = 0;
  uint64_t reflectedOnce = 0, transmittedOnce = 0;  // paths that left after exactly one collision
  // Exit-cosine bins (settings.cosineBins), every path that left, and those scattered once.
  std::vector<uint64_t> reflectedByCosine, transmittedByCosine, reflectedOnceByCosine, transmittedOnceByCosine;
  // Radial bins (settings.radiusEdges; one fewer than edges): the distance, in the surface plane,
  // from the point where the beam entered to where the path left (r past the last edge: no bin).
  std::vector<uint64_t> reflectedByRadius, transmittedByRadius, reflectedOnceByRadius, transmittedOnceByRadius;

  // A count as a fraction of the incident power, and its standard error (binomial).
  double fraction(uint64_t count) const;
  double standardError(uint64_t count) const;

  double reflectance() const { return fraction(reflected); }
  double scatteredTransmittance() const { return fraction(transmitted); }
  double transmittance() const { return unscattered + fraction(transmitted); }
  double absorptance() const { return fraction(absorbed); }

  // Mean radiance over exit-cosine bin i (weighted by mu, as power is) per unit irradiance on
  // the surface, in 1/sr: fraction / (pi (mu_hi^2 - mu_lo^2)). Under diffuse light the irradiance
  // is pi times the sky's radiance.
  double radianceInCosineBin(const std::vector<uint64_t>& bins, int i) const;
  // Mean exitance over radial bin i per unit incident power, in 1 / mfp^2:
  // fraction / (pi (r_hi^2 - r_lo^2)).
  double exitanceInRadiusBin(const std::vector<uint64_t>& bins, int i) const;
};

// Runs settings.paths paths. Throws Error (SS_INVALID_ARGUMENT) for settings out of range.
SlabTallies simulateSlab(const SlabSettings& settings);

// The exact unscattered transmittance of the settings' illumination: exp(-tau/mu0) or 2 E_3(tau).
double slabUnscatteredTransmittance(const SlabSettings& settings);

// The exponential integral E_n(x) = int_1^inf e^{-x t} / t^n dt = int_0^1 mu^{n-2} e^{-x/mu} dmu,
// n >= 1, x >= 0 (x > 0 for n = 1); E_n(infinity) = 0.
double exponentialIntegral(int n, double x);

}  // namespace subsplat
