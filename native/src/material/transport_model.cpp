#include "material/transport_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <mutex>
#include <sstream>
#include <string>

#include "transport/hfunction.h"
#include "transport/profile_table.h"
#include "transport/slab_table.h"
#include "transport/transport_data.h"
#include "util/error.h"

namespace subsplat {

namespace {

// Radial bins with fewer paths than this end a profile: beyond, the Monte Carlo's noise is over
// 30 % a bin, and less than 1e-4 of the energy is left.
constexpr uint64_t kLeastCount = 10;

const std::string& embedded(const char* name) {
  static std::mutex mutex;
  static std::vector<std::pair<std::string, std::string>> texts;
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& t : texts)
    if (t.first == name) return t.second;
  const char* text = transportData(name);
  if (!text) fail(SS_INTERNAL_ERROR, std::string("transport table ") + name + " is not embedded in the library");
  texts.emplace_back(name, text);
  return texts.back().second;
}

// The half-space's radial shapes, normalised, per table albedo: ln S at the bin centres.
struct HalfSpaceShapes {
  std::vector<double> root;                 // sqrt(1 - a) per table albedo, decreasing
  std::vector<double> lnRho;                // bin centres, mean free paths
  std::vector<std::vector<double>> lnShape;
  std::vector<size_t> knots;                // usable knots per albedo

  static const HalfSpaceShapes& instance() {
    static const HalfSpaceShapes shapes(readProfileTable(embedded("half_space_profiles.txt")));
    return shapes;
  }

  explicit HalfSpaceShapes(const ProfileTable& table) {
    const ProfileTableSpec& spec = table.spec;
    const std::vector<double>& edges = spec.radiusEdges;
    size_t bins = edges.size() - 1;
    require(bins >= 4 && spec.thicknesses.size() == 1 && std::isinf(spec.thicknesses[0]),
            "half-space table: one thickness (the half-space) and radial bins");
    for (size_t k = 0; k < bins; ++k)
      lnRho.push_back(std::log(k == 0 ? 0.5 * edges[1] : std::sqrt(edges[k] * edges[k + 1])));
    for (size_t i = 0; i < spec.albedos.size(); ++i) {
      const SlabTallies& t = table.at(i, 0);
      root.push_back(std::sqrt(1.0 - spec.albedos[i]));
      std::vector<double> ln(bins, -std::numeric_limits<double>::infinity());
      size_t usable = 0;
      for (size_t k = 0; k < bins; ++k) {
        uint64_t count = t.reflectedByRadius.at(k);
        if (count < kLeastCount) break;
        ln[k] = std::log(double(count) / (M_PI * (edges[k + 1] * edges[k + 1] - edges[k] * edges[k])));
        usable = k + 1;
      }
      require(usable >= 4, "half-space table: too few counts at albedo " + std::to_string(spec.albedos[i]));
      lnShape.push_back(std::move(ln));
      knots.push_back(usable);
    }
  }
};

// Energy of a power law S_k (rho / rho_k)^p over [rho_k, rho], 2 pi rho drho.
double powerLawEnergy(double rhoK, double sK, double p, double rho) {
  if (std::abs(p + 2.0) < 1e-9) return 2.0 * M_PI * sK * rhoK * rhoK * std::log(rho / rhoK);
  return 2.0 * M_PI * sK * rhoK * rhoK * (std::pow(rho / rhoK, p + 2.0) - 1.0) / (p + 2.0);
}

const SlabTable& slabTable() {
  static const SlabTable table = readSlabTable(embedded("slab_table.txt"));
  return table;
}

// The H-function's albedo: H needs a in (0, 1].
double hAlbedo(double a) { return std::clamp(a, 1e-9, 1.0); }

// Index coordinates of the texture layer (TransportTables): thickness (0 at tau = 0, 1 at the
// first slab, then one per step of the geometric grid) and cosine (0 at the first, 7 at mu = 1).
double thicknessCoordinate(double tau) {
  const std::vector<double>& t = slabTable().thicknesses;
  if (tau <= t[1]) return std::max(tau, 0.0) / t[1];
  double step = std::log(t[2] / t[1]);
  return std::min(1.0 + std::log(tau / t[1]) / step, double(t.size() - 1));
}
double cosineCoordinate(double mu) {
  double n = TransportTables::kCosines;
  return std::clamp(std::sqrt(std::clamp(mu, 0.0, 1.0)) * n - 1.0, 0.0, n - 1.0);
}

// R(1) at the nodes, embedded (transport/data/normal_incidence_albedo.txt, which
// solveNormalIncidenceAlbedoNodes wrote): solving them at run time took 0.3 s at every Blender start.
const std::vector<double>& normalIncidenceAlbedoNodes() {
  static const std::vector<double> nodes = [] {
    const char* text = transportData("normal_incidence_albedo.txt");
    require(text != nullptr, "the embedded normal-incidence albedo table is missing");
    std::vector<double> r;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') r.push_back(std::stod(line));
    require(r.size() == size_t(kAlbedoNodes) + 1, "the embedded normal-incidence albedo table has " +
                                                     std::to_string(r.size()) + " values, not " +
                                                     std::to_string(kAlbedoNodes + 1));
    return r;
  }();
  return nodes;
}

}  // namespace

std::vector<double> solveNormalIncidenceAlbedoNodes() {
  std::vector<double> r(kAlbedoNodes + 1);
  for (int k = 0; k <= kAlbedoNodes; ++k) {
    double s = double(k) / kAlbedoNodes, a = 1.0 - s * s;
    r[size_t(k)] = a > 0.0 ? halfSpaceAlbedo(HFunction(hAlbedo(a)), 1.0) : 0.0;
  }
  return r;
}

std::string writeNormalIncidenceAlbedoNodes(const std::vector<double>& nodes) {
  std::ostringstream out;
  out << "# R(1) = 1 - sqrt(1 - a) H(1), the half-space's albedo under a normal beam, at sqrt(1 - a) = k / "
      << kAlbedoNodes << ", k = 0 .. " << kAlbedoNodes << "\n"
      << "# written by subsplat_tables --normal-incidence-albedo (material/transport_model.h)\n";
  char value[32];
  for (double v : nodes) {
    std::snprintf(value, sizeof value, "%.17g\n", v);
    out << value;
  }
  return out.str();
}

double halfSpaceAlbedoAtNormalIncidence(double albedo) {
  if (!(albedo > 0.0)) return 0.0;
  if (albedo >= 1.0) return 1.0;
  // Cubic (Lagrange) through the 4 nodes around s: R is smooth in s (R = 1 - H(1) s + O(s^2) at 1,
  // a (1 - ln 2) / 2 + O(a^2) at 0).
  const std::vector<double>& r = normalIncidenceAlbedoNodes();
  double x = std::sqrt(1.0 - albedo) * kAlbedoNodes;
  int first = std::clamp(int(std::floor(x)) - 1, 0, kAlbedoNodes - 3);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    double w = 1.0;
    for (int j = 0; j < 4; ++j)
      if (j != i) w *= (x - (first + j)) / double(i - j);
    sum += w * r[size_t(first + i)];
  }
  return std::clamp(sum, 0.0, 1.0);
}

double tabulatedTotalReflectance(double albedo, double eta) {
  if (!(albedo > 0.0)) return 0.0;
  double total = halfSpaceAlbedoAtNormalIncidence(albedo);
  double plain = dipoleTotalReflectance(albedo, 1.0);
  return plain > 0.0 ? total * dipoleTotalReflectance(albedo, eta) / plain : total;
}

std::shared_ptr<const RadialProfile> makeMediumProfile(const DipoleChannel& channel, int model) {
  if (model == kProfileTabulated) return std::make_shared<TabulatedProfile>(channel);
  return std::make_shared<Dipole>(channel);
}

TabulatedProfile::TabulatedProfile(const DipoleChannel& c) {
  sigmaT_ = mediumExtinction(c);
  double a = mediumAlbedo(c);
  total_ = tabulatedTotalReflectance(a, c.eta);
  const HalfSpaceShapes& s = HalfSpaceShapes::instance();
  // Interpolate ln S between the two table albedos around sqrt(1 - a) (ln S is nearly linear in
  // it at a fixed radius: the tail goes as exp(-sqrt(3 (1 - a)) rho)).
  double root = std::sqrt(std::max(1.0 - a, 0.0));
  size_t i = 0;
  double f = 0.0;
  if (root >= s.root.front()) {
    i = 0, f = 0.0;
  } else if (root <= s.root.back()) {
    i = s.root.size() - 2, f = 1.0;
  } else {
    while (i + 1 < s.root.size() && s.root[i + 1] > root) ++i;
    f = (s.root[i] - root) / (s.root[i] - s.root[i + 1]);
  }
  size_t knots = std::min(s.knots[i], s.knots[i + 1]);
  for (size_t k = 0; k < knots; ++k) {
    rho_.push_back(std::exp(s.lnRho[k]));
    shape_.push_back(std::exp((1.0 - f) * s.lnShape[i][k] + f * s.lnShape[i + 1][k]));
  }
  for (size_t k = 0; k + 1 < knots; ++k) power_.push_back(std::log(shape_[k + 1] / shape_[k]) / std::log(rho_[k + 1] / rho_[k]));
  cumulative_.assign(knots, 0.0);
  cumulative_[0] = M_PI * rho_[0] * rho_[0] * shape_[0];
  for (size_t k = 0; k + 1 < knots; ++k)
    cumulative_[k + 1] = cumulative_[k] + powerLawEnergy(rho_[k], shape_[k], power_[k], rho_[k + 1]);
  double norm = cumulative_.back();
  for (double& v : shape_) v /= norm;
  for (double& v : cumulative_) v /= norm;
  for (size_t k = 0; k < knots; ++k) {
    lnRho_.push_back(std::log(rho_[k]));
    lnShape_.push_back(std::log(shape_[k]));
  }
  lnStep_ = knots > 2 ? (lnRho_.back() - lnRho_[1]) / double(knots - 2) : 1.0;
  inverseLnStep_ = 1.0 / lnStep_;
  lnSigmaT_ = std::log(sigmaT_);
  lnScale_ = std::log(total_ * sigmaT_ * sigmaT_);  // -inf where nothing scatters: exp gives 0
  for (size_t k = 0; k + 1 < knots; ++k) segmentEnergy_.push_back(2.0 * M_PI * shape_[k] * rho_[k] * rho_[k]);
}

size_t TabulatedProfile::segmentOf(double rho, double lnRho) const {
  // rho_[0] < rho < rho_.back() (lnRho its logarithm): the segment [rho_k, rho_k+1) holding it.
  if (rho < rho_[1]) return 0;
  size_t k = std::min(size_t(1.0 + (lnRho - lnRho_[1]) / lnStep_), rho_.size() - 2);
  while (k > 1 && rho < rho_[k]) --k;  // rounding at a knot
  while (k + 2 < rho_.size() && rho >= rho_[k + 1]) ++k;
  return k;
}

double TabulatedProfile::shapeEnergyWithin(double rho) const {
  if (rho <= rho_[0]) return M_PI * rho * rho * shape_[0];
  if (rho >= rho_.back()) return 1.0;
  // powerLawEnergy's, with the logarithm segmentOf needs anyway (kernel tables ask for it millions
  // of times a material): 2 pi S_k rho_k^2 ((rho / rho_k)^(p + 2) - 1) / (p + 2).
  double lnRho = std::log(rho);
  size_t k = segmentOf(rho, lnRho);
  double q = power_[k] + 2.0, x = lnRho - lnRho_[k];
  // exp - 1 rather than expm1 (3x the time here): its rounding, 1e-16 of the segment's energy, is
  // added to cumulative_[k]; near q = 0 the series' first terms.
  double growth = std::abs(q) < 1e-6 ? x * (1.0 + 0.5 * q * x) : (std::exp(q * x) - 1.0) / q;
  return cumulative_[k] + segmentEnergy_[k] * growth;
}

double TabulatedProfile::value(double r) const { return valueAtLog(r > 0.0 ? std::log(r) : -HUGE_VAL); }

double TabulatedProfile::energyWithin(double r) const { return total_ * shapeEnergyWithin(r * sigmaT_); }

int TransportTables::thicknessCount() { return int(slabTable().thicknesses.size()); }
double TransportTables::thickestSlab() { return slabTable().thicknesses.back(); }
double TransportTables::firstSlab() { return slabTable().thicknesses[1]; }
double TransportTables::thicknessLogStep() { return std::log(slabTable().thicknesses[2] / slabTable().thicknesses[1]); }

TransportTables::TransportTables(const std::array<DipoleChannel, 3>& channels) {
  const SlabTable& slab = slabTable();
  require(int(slab.cosines.size()) == kCosines, "slab table: expected 8 cosines");
  int nt = thicknessCount();
  texels_.assign(size_t(kWidth) * height() * 4, 0.0f);
  auto at = [&](int x, int y, int c) -> float& { return texels_[(size_t(y) * kWidth + size_t(x)) * 4 + size_t(c)]; };
  // sqrt(1 - a) of the slab table's albedos, with a = 0 (nothing scattered) in front.
  std::vector<double> roots{1.0};
  for (double a : slab.albedos) roots.push_back(std::sqrt(1.0 - a));
  for (int c = 0; c < 3; ++c) {
    double a = mediumAlbedo(channels[size_t(c)]);
    albedo_[size_t(c)] = a;
    extinction_[size_t(c)] = mediumExtinction(channels[size_t(c)]);
    root_[size_t(c)] = std::sqrt(std::max(1.0 - a, 0.0));
    HFunction h(hAlbedo(a));
    for (int k = 0; k < kHSamples; ++k) {
      double t = double(k) / (kHSamples - 1);
      at(k, 0, c) = a > 0.0 ? float(h(t * t)) : 1.0f;
    }
    double r1 = a > 0.0 ? halfSpaceAlbedo(h, 1.0) : 0.0;
    // The slab table at this albedo: linear in sqrt(1 - a) between its two neighbours (entry 0 of
    // `roots` is a = 0, whose slabs neither reflect nor scatter anything through).
    double root = root_[size_t(c)];
    size_t j = 0;
    while (j + 2 < roots.size() && roots[j + 1] > root) ++j;
    double f = std::clamp((roots[j] - root) / (roots[j] - roots[j + 1]), 0.0, 1.0);
    auto slabValue = [&](const std::vector<float>& values, size_t entryIndex, size_t stride, size_t offset) {
      // entryIndex over (thickness, mu0) of one albedo; albedo index j - 1 (-1: a = 0).
      double lo = j == 0 ? 0.0 : values[((j - 1) * nt * kCosines + entryIndex) * stride + offset];
      double hi = values[(j * nt * kCosines + entryIndex) * stride + offset];
      return (1.0 - f) * lo + f * hi;
    };
    for (int k = 0; k < nt; ++k)
      for (int i = 0; i < kCosines; ++i) {
        size_t entry = size_t(k) * kCosines + size_t(i);
        double r = slabValue(slab.reflectance, entry, 1, 0);
        at(i, 1 + k, c) = r1 > 0.0 ? float(r / r1) : 0.0f;
        for (int m = 0; m < kCosines; ++m)
          at(m, 1 + nt + k * kCosines + i, c) = float(slabValue(slab.transmitted, entry, kCosines, size_t(m)));
      }
  }
}

double TransportTables::h(int c, double mu) const {
  double x = std::sqrt(std::clamp(mu, 0.0, 1.0)) * (kHSamples - 1);
  int k = std::min(int(x), kHSamples - 2);
  double f = x - k;
  return (1.0 - f) * texel(k, 0, c) + f * texel(k + 1, 0, c);
}

double TransportTables::incidence(int c, double tau, double mu0) const {
  double a = albedo_[size_t(c)];
  if (!(a > 0.0)) return 0.0;
  if (!(tau < thickestSlab())) {  // a half-space: R(mu0) / R(1) from H
    double root = root_[size_t(c)];
    return (1.0 - root * h(c, mu0)) / (1.0 - root * h(c, 1.0));
  }
  double u = thicknessCoordinate(tau), v = cosineCoordinate(mu0);
  int k = std::min(int(u), thicknessCount() - 2), i = std::min(int(v), kCosines - 2);
  double fu = u - k, fv = v - i;
  return (1 - fu) * ((1 - fv) * texel(i, 1 + k, c) + fv * texel(i + 1, 1 + k, c)) +
         fu * ((1 - fv) * texel(i, 2 + k, c) + fv * texel(i + 1, 2 + k, c));
}

double TransportTables::beamCentroid(int c, double mu0) const {
  double root = root_[size_t(c)];
  double t = std::sqrt(std::clamp(mu0, 0.0, 1.0)), x = t * (kHSamples - 1);
  int k = std::min(int(x), kHSamples - 2);
  double f = x - k;
  auto slope = [&](int j) {  // dH/dt at sample j: central, second-order one-sided at the ends
    const int n = kHSamples - 1;
    if (j == 0) return (-3.0 * texel(0, 0, c) + 4.0 * texel(1, 0, c) - texel(2, 0, c)) * 0.5 * n;
    if (j == n) return (3.0 * texel(n, 0, c) - 4.0 * texel(n - 1, 0, c) + texel(n - 2, 0, c)) * 0.5 * n;
    return (texel(j + 1, 0, c) - texel(j - 1, 0, c)) * 0.5 * n;
  };
  double dHdt = (1.0 - f) * slope(k) + f * slope(k + 1);
  double r = 1.0 - root * h(c, mu0);
  if (!(albedo_[size_t(c)] > 0.0) || !(r > 0.0)) return 1.0;
  return 1.0 - root * 0.5 * t * dHdt / r;  // mu0 dH/dmu = (t / 2) dH/dt
}

double TransportTables::exit(int c, double mu0, double mu) const {
  double a = albedo_[size_t(c)];
  mu0 = std::clamp(mu0, 1e-3, 1.0);
  mu = std::clamp(mu, 0.0, 1.0);
  double h0 = h(c, mu0);
  double r = 1.0 - root_[size_t(c)] * h0;
  if (!(a > 0.0) || !(r > 0.0)) return 1.0;
  return a * h0 * h(c, mu) / (4.0 * (mu0 + mu) * r);
}

double TransportTables::transmitted(int c, double tau, double mu0, double mu) const {
  if (!(tau < thickestSlab()) || !(tau > 0.0)) return 0.0;
  int nt = thicknessCount();
  double u = thicknessCoordinate(tau), v0 = cosineCoordinate(mu0), v = cosineCoordinate(mu);
  int k = std::min(int(u), nt - 2), i = std::min(int(v0), kCosines - 2), m = std::min(int(v), kCosines - 2);
  double fu = u - k, f0 = v0 - i, fm = v - m;
  // Linear in mu at the four (thickness, mu0) nodes around (tau, mu0), then between those in ln T
  // (T falls off about exponentially with tau / mu0), linearly where one of them is 0.
  double corner[4], logSum = 0.0, linear = 0.0;
  bool positive = true;
  for (int n = 0; n < 4; ++n) {
    int dk = n >> 1, di = n & 1;
    int row = 1 + nt + (k + dk) * kCosines + i + di;
    corner[n] = (1 - fm) * texel(m, row, c) + fm * texel(m + 1, row, c);
    double w = (dk ? fu : 1 - fu) * (di ? f0 : 1 - f0);
    positive = positive && corner[n] > 0.0;
    logSum += w * std::log(std::max(corner[n], 1e-300));
    linear += w * corner[n];
  }
  return positive ? std::exp(logSum) : linear;
}

double sideWeight(double cosine) {
  double x = std::clamp(cosine + 0.5, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace subsplat
