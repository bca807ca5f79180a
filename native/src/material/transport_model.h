// The TABULATED profile model (issue 19; docs/TRANSPORT.md, "The TABULATED model"): the
// translucency of a homogeneous medium from exact solutions of light transport in an index-matched,
// isotropically scattering medium instead of the classical dipole. Per colour channel, with the
// single-scattering albedo a = sigma_s' / (sigma_a + sigma_s') and lengths in mean free paths
// 1 / sigma_t (sigma_t = sigma_a + sigma_s'):
//
//   - the radial profile P(r): the half-space's reflectance profile under a normal beam, tabulated by
//     the slab Monte Carlo (transport/data/half_space_profiles.txt), interpolated in sqrt(1 - a),
//     scaled to carry exactly R(1) = 1 - sqrt(1 - a) H(1) (hfunction.h);
//   - incidence: the light entering at x_i counts R(mu0) / R(1) of it, or, where the part is a
//     slab thinner than the table's thickest (thin parts, below), the slab's R(tau, mu0) / R(1)
//     (transport/data/slab_table.txt, adding-doubling);
//   - exit: the radiance leaving at mu is the exitance over pi times the half-space's exit factor
//     X(mu0, mu) = pi a H(mu0) H(mu) / (4 pi (mu0 + mu)) / R(mu0) (so that a slab under a sun
//     radiates exactly a H H / (4 pi (mu0 + mu)); X = 1 for a Lambertian exit), with mu0 the mean
//     incidence cosine of the light that reached x_o, weighted by its exitance;
//   - thin parts: a part the light crosses over a distance d at mu0 is a slab of thickness
//     tau = d mu0 (in the share slabLikeness of its entry and exit normals; the rest counts as a
//     half-space); light leaves its far side as the slab's scattered transmission T(tau, mu0, mu)
//     times the irradiance where it entered, and the splats between surfaces facing apart
//     (n_i . n_o < 0) are weighted out (sideWeight) so that it is not counted twice.
// For eta > 1 the profile's total is scaled by the dipole's boundary factor
// Rd_total(eta) / Rd_total(1) (Jensen et al. 2001); the Fresnel transmittances at entry and exit are
// the pipeline's, as for the dipole. That part is the dipole's approximation, not checked against
// the truth (a delta light cannot reach a medium behind a smooth refracting boundary in the twin).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "material/dipole.h"
#include "material/radial_profile.h"

namespace subsplat {

// SsMaterialDesc::profile_model.
enum ProfileModel : int { kProfileDipole = 0, kProfileTabulated = 1 };

// The single-scattering albedo and extinction (1/mm) of a channel.
inline double mediumAlbedo(const DipoleChannel& c) { return c.sigmaSPrime / (c.sigmaA + c.sigmaSPrime); }
inline double mediumExtinction(const DipoleChannel& c) { return c.sigmaA + c.sigmaSPrime; }

// R(1) = 1 - sqrt(1 - a) H(1), the half-space's albedo under a normal beam, for a in [0, 1]: cubic
// between 257 nodes in sqrt(1 - a) solved once, within 3e-9 (and 2e-7 of itself) of the
// H-function's (TabulatedModel.NormalIncidenceAlbedoIsTheHFunctions).
double halfSpaceAlbedoAtNormalIncidence(double albedo);
// Its nodes: R(1) at sqrt(1 - a) = k / kAlbedoNodes, k = 0 .. kAlbedoNodes. The library reads them
// from transport/data/normal_incidence_albedo.txt, which subsplat_tables --normal-incidence-albedo
// writes from solveNormalIncidenceAlbedoNodes (an H-function a node).
constexpr int kAlbedoNodes = 256;
std::vector<double> solveNormalIncidenceAlbedoNodes();
std::string writeNormalIncidenceAlbedoNodes(const std::vector<double>& nodes);
// The total the TABULATED profile carries at normal incidence: R(1) of the half-space, times the
// boundary factor for eta > 1. The add-on's Principled conversion inverts it (ssTotalReflectance).
double tabulatedTotalReflectance(double albedo, double eta);

// The profile of one channel under `model` (kProfileDipole: material/dipole.h).
std::shared_ptr<const RadialProfile> makeMediumProfile(const DipoleChannel& channel, int model);

// The half-space's radial profile under a normal beam, from the embedded Monte Carlo table.
// Lengths in millimetres, P in 1/mm^2, as every RadialProfile.
class TabulatedProfile final : public RadialProfile {
 public:
  explicit TabulatedProfile(const DipoleChannel& channel);

  double value(double r) const override;
  // value(r) from ln r (r in mm), with no logarithm of its own: the channels' knots lie at the same
  // rho (the table's bins), so a caller evaluating three channels at one r takes one logarithm, not
  // three. value(r) is valueAtLog(ln r). (REFERENCE, which evaluates P some 10^8 times a frame,
  // reads a table made from it: reference/squared_radius_table.h.)
  double valueAtLog(double lnR) const;
  double energyWithin(double r) const override;
  double totalEnergy() const override { return total_; }
  double scaleHint() const override { return 1.0 / sigmaT_; }
  // mm: within innerRadius P is constant (the table's first bin), from outerRadius on it is 0.
  double innerRadius() const { return rho_.front() / sigmaT_; }
  double outerRadius() const { return rho_.back() / sigmaT_; }

 private:
  double total_ = 0.0, sigmaT_ = 1.0;
  // The shape S(rho) (rho in mean free paths, integral of S 2 pi rho drho = 1): constant below
  // rho_0, a power law between knots, 0 beyond the last. cumulative_[k]: the integral to rho_k.
  std::vector<double> rho_, shape_, power_, cumulative_;
  // ln rho_k and ln S_k; from knot 1 on the knots are geometric (the table's bins), so the segment
  // of a radius is found from its logarithm (REFERENCE evaluates P some 10^8 times a frame).
  std::vector<double> lnRho_, lnShape_;
  std::vector<double> segmentEnergy_;  // 2 pi S_k rho_k^2
  double lnStep_ = 1.0, inverseLnStep_ = 1.0;
  double lnSigmaT_ = 0.0, lnScale_ = 0.0;  // ln sigma_T, ln (total sigma_T^2)
  size_t segmentOf(double rho, double lnRho) const;
  double shapeEnergyWithin(double rho) const;
};

inline double TabulatedProfile::valueAtLog(double lnR) const {
  double lnRho = lnR + lnSigmaT_;
  if (lnRho <= lnRho_[0]) return total_ * shape_[0] * sigmaT_ * sigmaT_;
  if (lnRho >= lnRho_.back()) return 0.0;
  // The segment from the bins' logarithmic step. Where rounding puts a radius at a knot into the
  // neighbouring segment, that segment's power law meets this one at the knot (S is continuous):
  // the value differs by the rounding.
  size_t k = lnRho < lnRho_[1] ? 0 : std::min(size_t(1.0 + (lnRho - lnRho_[1]) * inverseLnStep_), lnRho_.size() - 2);
  return std::exp(lnScale_ + lnShape_[k] + power_[k] * (lnRho - lnRho_[k]));  // total sigma_T^2 S_k (rho / rho_k)^p_k
}

// One translucent material's angular and thin-part tables, laid out as the GPU's texture layer
// (pipeline/material_tables.cpp) and evaluated here exactly as the shaders evaluate them
// (common.glsl), for REFERENCE and the tests. RGBA texels (alpha unused), kWidth per row:
//   row 0:                  H(mu) per channel at t = k / 32, mu = t^2 (k = 0 .. 32);
//   rows 1 .. nt:           the incidence factor R(tau, mu0) / R(1), x = the mu0 index;
//   rows 1 + nt + 8 tau + i: T(tau, mu0_i, mu), x = the mu index.
// Thicknesses and cosines are transport/slab_table.h's (tau = 0 first; cosines (j / 8)^2,
// j = 1 .. 8); beyond the last thickness the part counts as a half-space.
class TransportTables {
 public:
  static constexpr int kWidth = 33;
  static constexpr int kHSamples = 33;
  static constexpr int kCosines = 8;
  explicit TransportTables(const std::array<DipoleChannel, 3>& channels);

  static int thicknessCount();
  static double thickestSlab();           // mean free paths
  static double firstSlab();              // the thinnest slab after tau = 0
  static double thicknessLogStep();       // ln of the grid's ratio
  static int height() { return 1 + thicknessCount() * (1 + kCosines); }
  const std::vector<float>& texels() const { return texels_; }
  const std::array<double, 3>& albedo() const { return albedo_; }
  const std::array<double, 3>& extinction() const { return extinction_; }  // 1/mm

  // H(mu) of channel c, linear in sqrt(mu) between the samples.
  double h(int c, double mu) const;
  // R(tau, mu0) / R(1): tau in mean free paths, infinity (or beyond the table) for a half-space.
  double incidence(int c, double tau, double mu0) const;
  // X(mu0, mu).
  double exit(int c, double mu0, double mu) const;
  // T(tau, mu0, mu), 1/sr per unit irradiance; 0 beyond the table's thickest slab.
  double transmitted(int c, double tau, double mu0, double mu) const;
  // The mean distance along a beam entering the half-space at mu0, in mean free paths, of the first
  // collision of the light the half-space reflects: s(mu0) = 1 + mu0 R'(mu0) / R(mu0), with
  // R = 1 - sqrt(1 - a) H (the collision at s lies at depth s mu0, and R(mu0) is the Laplace
  // transform of the escape probability over depth). After its first collision a path walks
  // isotropically, so the reflected light's centroid on the surface is s(mu0) sin(theta) ahead of
  // the entry point along the beam (docs/TRANSPORT.md, "The entry's forward shift"). dH/dt
  // (t = sqrt(mu)) is the samples' central difference, linear in t between them; 1 at a = 0.
  double beamCentroid(int c, double mu0) const;

 private:
  std::array<double, 3> albedo_{}, extinction_{}, root_{};  // root: sqrt(1 - a)
  std::vector<float> texels_;
  float texel(int x, int y, int c) const { return texels_[(size_t(y) * kWidth + size_t(x)) * 4 + size_t(c)]; }
};

// The share of the light that entered at a surface of normal ni (facing the light) which reaches a
// surface of normal no (facing the camera) through the splatting: 1 where they face the same way,
// 0 where they face apart (the light then crossed the part: TransportTables::transmitted); a smooth
// step between n_i . n_o = -0.5 and 0.5.
double sideWeight(double cosine);
// How much a part is a slab between where the light enters (normal ne, facing the light) and where
// it leaves (normal nx): 1 where the two faces are opposed (ne . nx <= -0.5, a slab), 0 where they
// face the same way (ne . nx >= 0.5: the edge of a wedge, a sphere's cap near its terminator, which
// the slab tables do not describe and which counts as a half-space); 1 - sideWeight. The incidence
// factor is the slab's R(tau, mu0) in this share and the half-space's in the rest; the transmission
// term takes this share of the slab's T.
inline double slabLikeness(double cosine) { return 1.0 - sideWeight(cosine); }

}  // namespace subsplat
