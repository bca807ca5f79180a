#include "material/splat_kernel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <list>
#include <mutex>
#include <system_error>
#include <thread>

#include "material/transport_model.h"

namespace subsplat {

namespace {

std::atomic<uint64_t> kernelsBuilt{0};

bool sameDipole(const DipoleMaterial& a, const DipoleMaterial& b) {
  for (size_t c = 0; c < 3; ++c)
    if (a.channels[c].sigmaA != b.channels[c].sigmaA || a.channels[c].sigmaSPrime != b.channels[c].sigmaSPrime ||
        a.channels[c].eta != b.channels[c].eta)
      return false;
  return a.mmPerUnit == b.mmPerUnit && a.model == b.model;
}

}  // namespace

std::shared_ptr<const SplatKernel> SplatKernel::forDipole(const DipoleMaterial& material) {
  static std::mutex mutex;
  static std::list<std::pair<DipoleMaterial, std::shared_ptr<const SplatKernel>>> recent;  // newest first
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (auto it = recent.begin(); it != recent.end(); ++it)
      if (sameDipole(it->first, material)) {
        recent.splice(recent.begin(), recent, it);
        return recent.front().second;
      }
  }
  // Built outside the lock: another thread may build the same kernel meanwhile; both are right.
  auto kernel = std::make_shared<const SplatKernel>(material);
  std::lock_guard<std::mutex> lock(mutex);
  recent.emplace_front(material, kernel);
  if (recent.size() > kDipoleCacheSize) recent.pop_back();
  return kernel;
}

uint64_t SplatKernel::builtCount() { return kernelsBuilt.load(); }

SplatKernel::SplatKernel(const DipoleMaterial& m)
    : SplatKernel(Channels{makeMediumProfile(m.channels[0], m.model), makeMediumProfile(m.channels[1], m.model),
                           makeMediumProfile(m.channels[2], m.model)},
                  m.mmPerUnit) {}

SplatKernel::SplatKernel(Channels channels, double mmPerUnit) : SplatKernel(std::move(channels), mmPerUnit, 0.0) {}

SplatKernel::SplatKernel(Channels channels, double mmPerUnit, double supportRadius)
    : channels_(std::move(channels)), mmPerUnit_(mmPerUnit), supportRadius_(supportRadius) {
  for (int c = 0; c < 3; ++c) {
    const RadialProfile& profile = *channels_[size_t(c)];
    totalReflectance_[c] = profile.totalEnergy();
    effectiveRange_[c] = profile.radiusForEnergy(kEffectiveRangeEnergy) / mmPerUnit_;
    if (!(supportRadius > 0.0))
      supportRadius_ = std::max(supportRadius_, profile.radiusForEnergy(kSupportEnergy) / mmPerUnit_);
  }
  // An empty profile (all of P zero) still gets a finite support.
  if (!(supportRadius_ > 0.0)) supportRadius_ = channels_[0]->scaleHint() / mmPerUnit_;
  for (int c = 0; c < 3; ++c) {
    double kept = channels_[size_t(c)]->energyWithin(supportRadius_ * mmPerUnit_);
    normalisation_[c] = kept > 0.0 ? totalReflectance_[c] / kept : 0.0;
  }

  ++kernelsBuilt;
}

const std::vector<float>& SplatKernel::table() const {
  std::call_once(tableBuilt_, [this] {
    std::vector<float> table(size_t(kSizeA) * kSizeD * 4, 0.0f);
    // Rows side by side on the machine's cores (the profiles are immutable): a dipole's table took
    // 0.2 s on one core, the edit basis's six about a second (docs/MATERIAL_EDIT.md).
    auto rows = [&](int first, int step) {
      for (int ia = first; ia < kSizeA; ia += step) {
        double sigma = tableSigma(ia, supportRadius_);
        for (int id = 0; id < kSizeD; ++id) {
          double d = tableDistance(id, sigma, supportRadius_);
          float* texel = &table[(size_t(ia) * kSizeD + id) * 4];
          std::array<double, 3> average = footprintAverages(d, sigma);
          for (int c = 0; c < 3; ++c) texel[c] = float(average[size_t(c)]);
        }
      }
    };
    const int threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    std::vector<std::thread> helpers;
    int started = 1;  // rows t, t + threads, ... for t < started go to helpers; this thread does the rest
    try {
      for (; started < threads; ++started) helpers.emplace_back(rows, started, threads);
    } catch (const std::system_error&) {  // no more threads to be had
    }
    rows(0, threads);
    for (int t = started; t < threads; ++t) rows(t, threads);
    for (std::thread& helper : helpers) helper.join();
    table_ = std::move(table);
  });
  return table_;
}

double SplatKernel::tableSigma(int ia, double supportRadius) {
  double s = kMinLog2 + (kMaxLog2 - kMinLog2) * ia / (kSizeA - 1);
  return supportRadius * std::exp2(s);
}

double SplatKernel::tableDistance(int id, double sigma, double supportRadius) {
  double t = double(id) / (kSizeD - 1);
  return t * t * (kFootprintReach * sigma + supportRadius);
}

std::vector<float> SplatKernel::minimalRadiusTable(double epsilon) const {
  return minimalRadiusTable({{this, 1.0}}, epsilon);
}

std::vector<float> SplatKernel::minimalRadiusTable(
    const std::vector<std::pair<const SplatKernel*, double>>& kernels, double epsilon) {
  // Mean normalised profile P(r) r on [0, 1] and its tail integrals.
  constexpr int kFine = 4096;
  std::vector<double> profile(kFine + 1, 0.0), tail(kFine + 2, 0.0);
  double weights = 0.0;
  for (const auto& [kernel, weight] : kernels) weights += weight;
  for (const auto& [kernel, weight] : kernels) {
    // All channels over the longest range R_P (the multiresolution ranges are
    // R_P max x R-bar): the steep part of every channel stays below R-bar.
    const auto& range = kernel->effectiveRange_;
    double rangeMm = std::max({range[0], range[1], range[2]}) * kernel->mmPerUnit_;
    for (int c = 0; c < 3; ++c) {
      const RadialProfile& channel = *kernel->channels_[size_t(c)];
      double energy = channel.energyWithin(rangeMm) / (2.0 * M_PI);  // integral of P(s) s ds
      if (!(energy > 0.0) || !(rangeMm > 0.0) || !(weights > 0.0)) continue;
      // C of eq. 16, averaged over channels and profiles.
      double scale = rangeMm * rangeMm / energy / 3.0 * weight / weights;
      for (int i = 0; i <= kFine; ++i) {
        double r = double(i) / kFine;
        profile[size_t(i)] += scale * channel.value(r * rangeMm) * r;
      }
    }
  }
  for (int i = kFine - 1; i >= 0; --i) tail[i] = tail[i + 1] + 0.5 * (profile[i] + profile[i + 1]) / kFine;
  auto at = [&](double r) {  // P(r) r, linear between samples
    double x = std::clamp(r, 0.0, 1.0) * kFine;
    int i = std::min(int(x), kFine - 1);
    return profile[i] + (profile[i + 1] - profile[i]) * (x - i);
  };
  auto tailIntegral = [&](double r) {
    double x = std::clamp(r, 0.0, 1.0) * kFine;
    int i = std::min(int(x), kFine - 1);
    return tail[i] - (x - i) * 0.5 * (profile[i] + at(r)) / kFine;
  };
  std::vector<float> table(kRadiusTableSize, 0.0f);
  constexpr int kSteps = 256;
  for (int it = 0; it < kRadiusTableSize; ++it) {
    double T = std::exp2(kMinLog2T + (kMaxLog2T - kMinLog2T) * it / (kRadiusTableSize - 1));
    double radius = 0.0;
    for (int j = kSteps; j >= 0; --j) {  // from r = 1 inwards until the error exceeds epsilon
      double r = double(j) / kSteps;
      double sum = 0.0;
      int count = int(std::floor((1.0 - r) * T));
      for (int m = 0; m <= count; ++m) sum += at(r + m / T);
      if (std::abs(sum / T - tailIntegral(r)) >= epsilon) {
        radius = std::min(1.0, double(j + 1) / kSteps);
        break;
      }
    }
    table[size_t(it)] = float(radius);
  }
  return table;
}

double SplatKernel::energyWithin(int c, double r) const {
  r = std::min(r, supportRadius_);
  return normalisation_[size_t(c)] * channels_[size_t(c)]->energyWithin(r * mmPerUnit_);
}

namespace {

// e^{-g} e^{-x} I_0(x) for g >= 0: a Gaussian factor times the exponentially scaled modified Bessel
// function (Abramowitz & Stegun 9.8.1 and 9.8.2, |error| < 2e-7 relative), with one exponential
// for both factors where the series needs its own.
double gaussianTimesBesselI0Scaled(double g, double x) {
  if (x < 3.75) {
    double t = (x / 3.75) * (x / 3.75);
    double i0 = 1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (0.2659732 +
                t * (0.0360768 + t * 0.0045813)))));
    return i0 * std::exp(-(g + x));
  }
  double t = 3.75 / x;
  return std::exp(-g) *
         (0.39894228 + t * (0.01328592 + t * (0.00225319 + t * (-0.00157565 + t * (0.00916281 +
          t * (-0.02057706 + t * (0.02635537 + t * (-0.01647633 + t * 0.00392377)))))))) /
         std::sqrt(x);
}

}  // namespace

double SplatKernel::footprintAverage(int c, double d, double sigma) const {
  return footprintAverages(d, sigma)[size_t(c)];
}

std::array<double, 3> SplatKernel::footprintAverages(double d, double sigma) const {
  // The mean of a 2D Gaussian centred at distance d over a circle of radius r
  // is exp(-(d^2 + r^2) / 2 sigma^2) I_0(d r / sigma^2) / (2 pi sigma^2).
  // Integrate it against the radial energy dE(r) (a Stieltjes sum, so the
  // profile's peak near r = 0 is never missed, however small z_r is).
  std::array<double, 3> sum{0.0, 0.0, 0.0};
  double reach = kFootprintReach * sigma;
  double lo = std::max(0.0, d - reach), hi = std::min(d + reach, supportRadius_);
  if (hi <= lo) return sum;
  constexpr int kSteps = 64;
  double step = (hi - lo) / kSteps;
  double e0[3];
  for (int c = 0; c < 3; ++c) e0[c] = energyWithin(c, lo);
  for (int j = 0; j < kSteps; ++j) {
    double r = lo + (j + 0.5) * step;
    double x = d * r / (sigma * sigma);
    double weight = gaussianTimesBesselI0Scaled((d - r) * (d - r) / (2 * sigma * sigma), x);
    for (int c = 0; c < 3; ++c) {
      double e1 = energyWithin(c, lo + (j + 1) * step);
      sum[size_t(c)] += weight * (e1 - e0[c]);
      e0[c] = e1;
    }
  }
  for (double& s : sum) s /= 2.0 * M_PI * sigma * sigma;
  return sum;
}

}  // namespace subsplat
