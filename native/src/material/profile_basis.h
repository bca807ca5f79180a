// A radial profile as a linear combination of piecewise polynomial basis functions (Xu et al. 2007,
// sec. 5): P(r) ~ sum_j c_j B_j(r). The transport of each B_j can be computed once for a view and
// its lights; a material edit then only projects the new profile onto the basis (issue 23,
// docs/MATERIAL_EDIT.md).
//
// The basis: B-splines of degree 1 (hats: the paper's piecewise linear basis, C0) or 2 (its
// piecewise quadratic, C1) on knots 0 = r_0 < ... < r_m = reach, clamped at both ends, so
// m + degree functions. Lengths are in a unit of the caller's (the edit's: the precomputed
// material's R_P); profiles are RadialProfiles in millimetres, placed by a scale (mm per unit).
//
// Coefficients are the least-squares projection in the plane's area measure, minimising
// integral (P - sum c_j B_j)^2 2 pi r dr over [0, reach]: what a pixel receives is P weighted by
// area, not by radius. The knots are the paper's: dynamic programming over a geometric grid of
// candidates, for the piecewise linear interpolant of a family of representative profiles; here
// the cost of an interval is the family's relative L1 error in the area measure (the bound of the
// relative error of the exitance it adds, whatever the irradiance), summed over the family.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "material/radial_profile.h"

namespace subsplat {

// A profile at a scale: P(r) of `profile` (mm) at r * mmPerUnit, per unit^2.
struct ScaledProfile {
  const RadialProfile* profile = nullptr;
  double mmPerUnit = 1.0;
};

class ProfileBasis {
 public:
  // knots: r_0 = 0 < r_1 < ... < r_m; degree 1 or 2.
  ProfileBasis(std::vector<double> knots, int degree);
  static ProfileBasis uniform(double reach, int intervals, int degree);
  // The knots minimising the family's summed relative L1 error of the piecewise linear
  // interpolant, among kCandidates geometric candidates in [reach * kFinestCandidate, reach].
  static constexpr int kCandidates = 256;
  static constexpr double kFinestCandidate = 1e-6;
  static ProfileBasis fitted(const std::vector<ScaledProfile>& family, double reach, int intervals, int degree);

  int size() const { return int(knots_.size()) - 1 + degree_; }
  // Where B_j is non-zero: [supportStart(j), supportEnd(j)].
  double supportStart(int j) const { return t_[size_t(j)]; }
  double supportEnd(int j) const { return t_[size_t(j + degree_ + 1)]; }
  // The integral of B_j over the disk of radius r, 2 pi s ds (exact).
  double energyWithin(int j, double r) const;
  int degree() const { return degree_; }
  double reach() const { return knots_.back(); }
  const std::vector<double>& knots() const { return knots_; }
  // B_j(r); 0 outside [0, reach].
  double value(int j, double r) const;
  // sum_j c_j B_j(r).
  double evaluate(const std::vector<double>& c, double r) const;
  // The integral of sum_j c_j B_j over the plane, 2 pi r dr (exact).
  double total(const std::vector<double>& c) const;
  // The least-squares coefficients of p (area measure).
  std::vector<double> project(const ScaledProfile& p) const;

  struct Error {
    double energy = 0.0;  // (total(c) - total of P) / total of P
    double l1 = 0.0;      // integral |sum c_j B_j - P| 2 pi r dr / total of P, P's tail past reach included
    double tail = 0.0;    // P's energy past reach / total of P
    // The largest error of the energy within a radius, max over r of
    // |integral_0^r (sum c_j B_j - P) 2 pi s ds| / total of P: the relative error of the light a
    // disk of any radius gathers (or a plane lit inside any circle), which a profile's shape
    // within a core far below a pixel does not change. At most l1.
    double cumulative = 0.0;
  };
  Error error(const ScaledProfile& p, const std::vector<double>& c) const;

 private:
  std::vector<double> knots_;  // distinct, increasing
  int degree_ = 1;
  std::vector<double> t_;      // the clamped knot vector
  std::vector<double> energyAtKnot_;  // energyWithin(j, r_k), size() x knots
  // B_j on interval k as a0 + a1 u + a2 u^2, u = r - r_k: size() x intervals x 3.
  std::vector<double> pieces_;
  // The basis functions non-zero on knot interval k: j = k .. k + degree.
  void valuesOnInterval(int k, double r, double* out) const;
  int intervalOf(double r) const;
  double pieceEnergy(int j, int k, double u) const;  // of B_j over [r_k, r_k + u]
};

// A profile as the splatting uses it (material/splat_kernel.h): cut at a support radius (a
// material's: the longest of its channels' radii holding SplatKernel::kSupportEnergy) and
// renormalised to keep its total. The edit path projects this, so that an edited image is the
// image FULL renders of the edited material.
class SupportedProfile final : public RadialProfile {
 public:
  SupportedProfile(std::shared_ptr<const RadialProfile> profile, double supportMm);
  double value(double r) const override { return r < supportMm_ ? scale_ * profile_->value(r) : 0.0; }
  double energyWithin(double r) const override;
  double totalEnergy() const override { return profile_->totalEnergy(); }
  double scaleHint() const override { return profile_->scaleHint(); }
  double support() const { return supportMm_; }

 private:
  std::shared_ptr<const RadialProfile> profile_;
  double supportMm_ = 0.0, scale_ = 1.0;
};

// B_j as a radial profile (lengths in the basis's unit), for its splat kernel table.
class BasisFunction final : public RadialProfile {
 public:
  BasisFunction(const ProfileBasis& basis, int j) : basis_(basis), j_(j) {}
  double value(double r) const override { return basis_.value(j_, r); }
  double energyWithin(double r) const override { return basis_.energyWithin(j_, r); }
  double totalEnergy() const override { return basis_.energyWithin(j_, basis_.reach()); }
  double scaleHint() const override { return basis_.supportEnd(j_) - basis_.supportStart(j_); }

 private:
  const ProfileBasis& basis_;
  int j_;
};

// A profile that owns its medium's profile.
struct OwnedProfile {
  std::shared_ptr<const RadialProfile> profile;
  double mmPerUnit = 1.0;
  ScaledProfile view() const { return {profile.get(), mmPerUnit}; }
};

// The edit basis (docs/MATERIAL_EDIT.md, "The basis"). Lengths are in units of the precomputed
// material's R_P (its longest channel's radius holding 95 % of the energy); the basis reaches
// kEditReach of them, so that an edit may lengthen the profile about twofold.
constexpr double kEditReach = 4.0;
// Random media for the knots (kCalibrationSeed) and for testing them (any other seed), each cut at
// its own support (SupportedProfile): per medium a reduced albedo with 1 - a' log-uniform in [1e-4, 0.6], the dipole or the TABULATED
// profile, eta 1.3, and an R_P log-uniform in [1/30, 2] units (a shorter channel of the same
// material, or an edit that lengthened it).
constexpr uint64_t kCalibrationSeed = 0x5eed0001, kEditTestSeed = 0x5eed0002;
std::vector<OwnedProfile> randomMediaFamily(uint64_t seed, int count);
// The basis of `intervals` intervals and `degree` for editing: knots fitted on kCalibrationMedia
// media of kCalibrationSeed (0.6 s). Built once per (intervals, degree) and kept.
constexpr int kCalibrationMedia = 48;
std::vector<double> fitEditKnots(int intervals, int degree);
// The basis MATERIAL_EDIT uses: piecewise quadratic on 16 fitted intervals (18 coefficients), the
// fewest coefficients whose error on the calibration media (ProfileBasis::Error::cumulative) is
// below 0.25 % on average and 1 % at most (subsplat_basis; docs/MATERIAL_EDIT.md, "The basis").
// Its knots are fitEditKnots(16, 2) as written here, so that no render fits them
// (ProfileBasis.TheEditKnotsAreTheFitOnTheCalibrationMedia checks them); editBasis returns them.
constexpr int kEditIntervals = 16, kEditDegree = 2;
constexpr double kEditKnots[kEditIntervals + 1] = {
    0, 0.00015084488197696783, 0.00085402730468507766, 0.0026643385163236631, 0.0056885446046613473,
    0.010323446161672295, 0.01774674932391445, 0.028899046961270259, 0.047059599480807422, 0.072591123945572919,
    0.11197441826572721, 0.18234065928691481, 0.29692599920711743, 0.48351831867853728, 0.83120290072966907,
    1.6810839550558765, 4};
const ProfileBasis& editBasis(int intervals, int degree);

}  // namespace subsplat
