#include "material/profile_basis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <utility>

#include "material/splat_kernel.h"
#include "material/transport_model.h"

namespace subsplat {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// Gauss-Legendre, 8 points on [-1, 1].
constexpr double kGaussX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                               0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
constexpr double kGaussW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                               0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

template <class F>
void gauss(double a, double b, F&& f) {
  double h = 0.5 * (b - a), m = 0.5 * (a + b);
  for (int i = 0; i < 8; ++i) f(m + h * kGaussX[i], h * kGaussW[i]);
}

// Quadrature points of [a, b] for a profile that may vary over decades within it: pieces at most
// twice as long as where they start (geometric down to b 2^-40 where a is 0), 8 Gauss points each.
template <class F>
void composite(double a, double b, F&& f) {
  if (!(b > a)) return;
  double lo = a > 0.0 ? a : b * std::ldexp(1.0, -40);
  if (a == 0.0) gauss(0.0, lo, f);
  if (b / lo <= 2.0) {
    for (int i = 0; i < 4; ++i) gauss(lo + (b - lo) * i / 4.0, lo + (b - lo) * (i + 1) / 4.0, f);
    return;
  }
  for (double x = lo; x < b;) {
    double next = std::min(2.0 * x, b);
    if (b - next < 1e-12 * b) next = b;
    gauss(x, next, f);
    x = next;
  }
}

// composite() over [a, b], split where p is cut (SupportedProfile): no Gauss piece straddles the step.
template <class F>
void compositeFor(const ScaledProfile& p, double a, double b, F&& f) {
  const auto* cut = dynamic_cast<const SupportedProfile*>(p.profile);
  double s = cut ? cut->support() / p.mmPerUnit : -1.0;
  if (s > a && s < b) {
    composite(a, s, f);
    composite(s, b, f);
  } else {
    composite(a, b, f);
  }
}

double profileAt(const ScaledProfile& p, double r) {
  return p.profile->value(r * p.mmPerUnit) * p.mmPerUnit * p.mmPerUnit;
}

}  // namespace

ProfileBasis::ProfileBasis(std::vector<double> knots, int degree) : knots_(std::move(knots)), degree_(degree) {
  if (degree_ != 1 && degree_ != 2) throw std::invalid_argument("profile basis: degree must be 1 or 2");
  if (knots_.size() < 2 || knots_.front() != 0.0) throw std::invalid_argument("profile basis: knots must start at 0");
  for (size_t i = 1; i < knots_.size(); ++i)
    if (!(knots_[i] > knots_[i - 1]) || !std::isfinite(knots_[i]))
      throw std::invalid_argument("profile basis: knots must increase");
  t_.assign(size_t(degree_), 0.0);
  t_.insert(t_.end(), knots_.begin(), knots_.end());
  t_.insert(t_.end(), size_t(degree_), knots_.back());
  // Each piece from its values at u = 0, h / 2, h (exact: degree <= 2), and the energies at the knots.
  size_t m = knots_.size() - 1;
  pieces_.assign(size_t(size()) * m * 3, 0.0);
  energyAtKnot_.assign(size_t(size()) * knots_.size(), 0.0);
  for (int j = 0; j < size(); ++j)
    for (size_t k = 0; k < m; ++k) {
      double h = knots_[k + 1] - knots_[k];
      double v[3], f0, f1, f2;
      valuesOnInterval(int(k), knots_[k], v);
      f0 = (j >= int(k) && j <= int(k) + degree_) ? v[j - int(k)] : 0.0;
      valuesOnInterval(int(k), knots_[k] + 0.5 * h, v);
      f1 = (j >= int(k) && j <= int(k) + degree_) ? v[j - int(k)] : 0.0;
      valuesOnInterval(int(k), knots_[k + 1], v);
      f2 = (j >= int(k) && j <= int(k) + degree_) ? v[j - int(k)] : 0.0;
      double* a = &pieces_[(size_t(j) * m + k) * 3];
      a[0] = f0;
      a[2] = 2.0 * (f2 - 2.0 * f1 + f0) / (h * h);
      a[1] = (f2 - f0) / h - a[2] * h;
      energyAtKnot_[size_t(j) * knots_.size() + k + 1] =
          energyAtKnot_[size_t(j) * knots_.size() + k] + pieceEnergy(j, int(k), h);
    }
}

double ProfileBasis::pieceEnergy(int j, int k, double u) const {
  const double* a = &pieces_[(size_t(j) * (knots_.size() - 1) + size_t(k)) * 3];
  double r0 = knots_[size_t(k)], u2 = u * u, u3 = u2 * u;
  // integral over [0, u] of (r0 + x)(a0 + a1 x + a2 x^2) 2 pi dx
  return kTwoPi * (r0 * (a[0] * u + a[1] * u2 / 2.0 + a[2] * u3 / 3.0) +
                   (a[0] * u2 / 2.0 + a[1] * u3 / 3.0 + a[2] * u3 * u / 4.0));
}

ProfileBasis ProfileBasis::uniform(double reach, int intervals, int degree) {
  std::vector<double> knots(size_t(intervals) + 1);
  for (int k = 0; k <= intervals; ++k) knots[size_t(k)] = reach * k / intervals;
  return ProfileBasis(std::move(knots), degree);
}

int ProfileBasis::intervalOf(double r) const {
  int m = int(knots_.size()) - 1;
  int k = int(std::upper_bound(knots_.begin(), knots_.end(), r) - knots_.begin()) - 1;
  return std::clamp(k, 0, m - 1);
}

// The non-zero functions on interval k at r (The NURBS Book, A2.2): out[q] is B_{k+q}.
void ProfileBasis::valuesOnInterval(int k, double r, double* out) const {
  int p = degree_, s = k + p;  // the span in t_
  double left[3], right[3];
  out[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = r - t_[size_t(s + 1 - j)];
    right[j] = t_[size_t(s + j)] - r;
    double saved = 0.0;
    for (int q = 0; q < j; ++q) {
      double temp = out[q] / (right[q + 1] + left[j - q]);
      out[q] = saved + right[q + 1] * temp;
      saved = left[j - q] * temp;
    }
    out[j] = saved;
  }
}

double ProfileBasis::value(int j, double r) const {
  if (r < 0.0 || r > reach() || j < 0 || j >= size()) return 0.0;
  int k = intervalOf(r);
  if (j < k || j > k + degree_) return 0.0;
  double v[3];
  valuesOnInterval(k, r, v);
  return v[j - k];
}

double ProfileBasis::evaluate(const std::vector<double>& c, double r) const {
  if (r < 0.0 || r > reach()) return 0.0;
  int k = intervalOf(r);
  double v[3];
  valuesOnInterval(k, r, v);
  double sum = 0.0;
  for (int q = 0; q <= degree_; ++q) sum += c[size_t(k + q)] * v[q];
  return sum;
}

double ProfileBasis::energyWithin(int j, double r) const {
  if (r <= 0.0 || j < 0 || j >= size()) return 0.0;
  size_t knots = knots_.size();
  if (r >= reach()) return energyAtKnot_[size_t(j) * knots + knots - 1];
  int k = intervalOf(r);
  return energyAtKnot_[size_t(j) * knots + size_t(k)] + pieceEnergy(j, k, r - knots_[size_t(k)]);
}

double ProfileBasis::total(const std::vector<double>& c) const {
  double sum = 0.0;
  for (size_t k = 0; k + 1 < knots_.size(); ++k)
    gauss(knots_[k], knots_[k + 1], [&](double r, double w) { sum += w * kTwoPi * r * evaluate(c, r); });
  return sum;
}

std::vector<double> ProfileBasis::project(const ScaledProfile& p) const {
  int n = size(), m = int(knots_.size()) - 1;
  std::vector<double> gram(size_t(n) * n, 0.0), rhs(size_t(n), 0.0);
  double v[3];
  for (int k = 0; k < m; ++k) {
    gauss(knots_[size_t(k)], knots_[size_t(k + 1)], [&](double r, double w) {  // exact: degree 2p + 1
      valuesOnInterval(k, r, v);
      for (int a = 0; a <= degree_; ++a)
        for (int b = 0; b <= degree_; ++b) gram[size_t(k + a) * n + size_t(k + b)] += w * kTwoPi * r * v[a] * v[b];
    });
    compositeFor(p, knots_[size_t(k)], knots_[size_t(k + 1)], [&](double r, double w) {
      valuesOnInterval(k, r, v);
      double f = w * kTwoPi * r * profileAt(p, r);
      for (int a = 0; a <= degree_; ++a) rhs[size_t(k + a)] += f * v[a];
    });
  }
  // Cholesky: the Gram matrix of independent functions is positive definite.
  for (int j = 0; j < n; ++j) {
    double d = gram[size_t(j) * n + size_t(j)];
    for (int q = 0; q < j; ++q) d -= gram[size_t(j) * n + size_t(q)] * gram[size_t(j) * n + size_t(q)];
    if (!(d > 0.0)) throw std::runtime_error("profile basis: singular Gram matrix");
    double l = std::sqrt(d);
    gram[size_t(j) * n + size_t(j)] = l;
    for (int i = j + 1; i < n; ++i) {
      double s = gram[size_t(i) * n + size_t(j)];
      for (int q = 0; q < j; ++q) s -= gram[size_t(i) * n + size_t(q)] * gram[size_t(j) * n + size_t(q)];
      gram[size_t(i) * n + size_t(j)] = s / l;
    }
  }
  std::vector<double> c(rhs);
  for (int i = 0; i < n; ++i) {
    for (int q = 0; q < i; ++q) c[size_t(i)] -= gram[size_t(i) * n + size_t(q)] * c[size_t(q)];
    c[size_t(i)] /= gram[size_t(i) * n + size_t(i)];
  }
  for (int i = n - 1; i >= 0; --i) {
    for (int q = i + 1; q < n; ++q) c[size_t(i)] -= gram[size_t(q) * n + size_t(i)] * c[size_t(q)];
    c[size_t(i)] /= gram[size_t(i) * n + size_t(i)];
  }
  return c;
}

ProfileBasis::Error ProfileBasis::error(const ScaledProfile& p, const std::vector<double>& c) const {
  Error e;
  double total = p.profile->totalEnergy();
  if (!(total > 0.0)) return e;
  double l1 = 0.0, within = 0.0, largest = 0.0;  // the quadrature's points come in increasing r
  for (size_t k = 0; k + 1 < knots_.size(); ++k)
    compositeFor(p, knots_[k], knots_[k + 1], [&](double r, double w) {
      double d = w * kTwoPi * r * (evaluate(c, r) - profileAt(p, r));
      l1 += std::abs(d);
      within += d;
      largest = std::max(largest, std::abs(within));
    });
  e.tail = std::max(total - p.profile->energyWithin(reach() * p.mmPerUnit), 0.0) / total;
  e.l1 = l1 / total + e.tail;
  e.cumulative = std::max(largest / total, e.tail);
  e.energy = (this->total(c) - total) / total;
  return e;
}

ProfileBasis ProfileBasis::fitted(const std::vector<ScaledProfile>& family, double reach, int intervals,
                                  int degree) {
  if (family.empty() || intervals < 1 || intervals > kCandidates || !(reach > 0.0))
    throw std::invalid_argument("profile basis: a family, 1 to kCandidates intervals and a positive reach");
  // Candidates: 0, then geometric from reach * kFinestCandidate to reach; each gap sampled at
  // kSamples midpoints, weighted by area.
  constexpr int kSamples = 4;
  const int n = kCandidates;
  std::vector<double> c(size_t(n) + 1);
  c[0] = 0.0;
  for (int i = 1; i <= n; ++i) c[size_t(i)] = reach * std::pow(kFinestCandidate, double(n - i) / double(n - 1));
  std::vector<double> sr, sw;  // sample radii and area weights, kSamples per gap
  for (int i = 0; i < n; ++i)
    for (int q = 0; q < kSamples; ++q) {
      double a = c[size_t(i)] + (c[size_t(i) + 1] - c[size_t(i)]) * q / kSamples;
      double b = c[size_t(i)] + (c[size_t(i) + 1] - c[size_t(i)]) * (q + 1) / kSamples;
      sr.push_back(0.5 * (a + b));
      sw.push_back(kTwoPi * 0.5 * (a + b) * (b - a));
    }
  size_t f = family.size();
  std::vector<double> atCandidate((size_t(n) + 1) * f), atSample(sr.size() * f), scale(f);
  for (size_t m = 0; m < f; ++m) {
    double total = family[m].profile->totalEnergy();
    scale[m] = total > 0.0 ? 1.0 / total : 0.0;
    for (int i = 0; i <= n; ++i) atCandidate[size_t(i) * f + m] = profileAt(family[m], c[size_t(i)]);
    for (size_t s = 0; s < sr.size(); ++s) atSample[s * f + m] = profileAt(family[m], sr[s]);
  }
  // cost(i, j): the family's relative L1 error of the linear interpolant between c_i and c_j.
  auto cost = [&](int i, int j) {
    double sum = 0.0, width = c[size_t(j)] - c[size_t(i)];
    for (size_t s = size_t(i) * kSamples; s < size_t(j) * kSamples; ++s) {
      double u = (sr[s] - c[size_t(i)]) / width;
      for (size_t m = 0; m < f; ++m) {
        double lin = (1.0 - u) * atCandidate[size_t(i) * f + m] + u * atCandidate[size_t(j) * f + m];
        sum += sw[s] * std::abs(atSample[s * f + m] - lin) * scale[m];
      }
    }
    return sum;
  };
  std::vector<double> costs(size_t(n + 1) * size_t(n + 1), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j <= n; ++j) costs[size_t(i) * (n + 1) + size_t(j)] = cost(i, j);
  // best[k][j]: the least cost of reaching candidate j in k intervals from 0.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> best(size_t(intervals + 1) * (n + 1), inf);
  std::vector<int> from(best.size(), -1);
  best[0] = 0.0;
  for (int k = 1; k <= intervals; ++k)
    for (int j = k; j <= n; ++j)
      for (int i = k - 1; i < j; ++i) {
        double b = best[size_t(k - 1) * (n + 1) + size_t(i)];
        if (b == inf) continue;
        double total = b + costs[size_t(i) * (n + 1) + size_t(j)];
        if (total < best[size_t(k) * (n + 1) + size_t(j)]) {
          best[size_t(k) * (n + 1) + size_t(j)] = total;
          from[size_t(k) * (n + 1) + size_t(j)] = i;
        }
      }
  std::vector<double> knots(size_t(intervals) + 1);
  for (int k = intervals, j = n; k >= 0; --k) {
    knots[size_t(k)] = c[size_t(j)];
    if (k > 0) j = from[size_t(k) * (n + 1) + size_t(j)];
  }
  knots.front() = 0.0;
  knots.back() = reach;
  return ProfileBasis(std::move(knots), degree);
}

SupportedProfile::SupportedProfile(std::shared_ptr<const RadialProfile> profile, double supportMm)
    : profile_(std::move(profile)), supportMm_(supportMm) {
  double kept = profile_->energyWithin(supportMm_), total = profile_->totalEnergy();
  scale_ = kept > 0.0 ? total / kept : 0.0;
}

double SupportedProfile::energyWithin(double r) const {
  return scale_ * profile_->energyWithin(std::min(r, supportMm_));
}

std::vector<OwnedProfile> randomMediaFamily(uint64_t seed, int count) {
  std::mt19937_64 engine(seed);
  auto uniform = [&]() { return double(engine() >> 11) * 0x1.0p-53; };
  std::vector<OwnedProfile> family;
  for (int i = 0; i < count; ++i) {
    double absorbed = 1e-4 * std::pow(0.6 / 1e-4, uniform());  // 1 - a'
    DipoleChannel channel;
    channel.sigmaSPrime = 1.0 - absorbed;
    channel.sigmaA = absorbed;
    channel.eta = 1.3;
    int model = (engine() & 1) ? kProfileTabulated : kProfileDipole;
    std::shared_ptr<const RadialProfile> medium = makeMediumProfile(channel, model);
    OwnedProfile p;
    p.profile = std::make_shared<SupportedProfile>(medium, medium->radiusForEnergy(SplatKernel::kSupportEnergy));
    double rangeUnits = (1.0 / 30.0) * std::pow(60.0, uniform());
    p.mmPerUnit = medium->radiusForEnergy(SplatKernel::kEffectiveRangeEnergy) / rangeUnits;
    family.push_back(std::move(p));
  }
  return family;
}

std::vector<double> fitEditKnots(int intervals, int degree) {
  std::vector<OwnedProfile> family = randomMediaFamily(kCalibrationSeed, kCalibrationMedia);
  std::vector<ScaledProfile> views;
  for (const OwnedProfile& p : family) views.push_back(p.view());
  return ProfileBasis::fitted(views, kEditReach, intervals, degree).knots();
}

const ProfileBasis& editBasis(int intervals, int degree) {
  static std::mutex mutex;
  static std::map<std::pair<int, int>, ProfileBasis> built;
  std::lock_guard<std::mutex> lock(mutex);
  auto found = built.find({intervals, degree});
  if (found != built.end()) return found->second;
  std::vector<double> knots = intervals == kEditIntervals && degree == kEditDegree
                                  ? std::vector<double>(std::begin(kEditKnots), std::end(kEditKnots))
                                  : fitEditKnots(intervals, degree);
  return built.emplace(std::make_pair(intervals, degree), ProfileBasis(std::move(knots), degree)).first->second;
}

}  // namespace subsplat
