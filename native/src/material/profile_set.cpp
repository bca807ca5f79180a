#include "material/profile_set.h"

#include "material/transport_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>

#include "material/splat_kernel.h"
#include "util/parallel.h"
#include "util/error.h"

namespace subsplat {

// ---------------------------------------------------------------- profiles

SegmentedProfile::SegmentedProfile(const float* logKnots, int segments, double radiusMm, int stride)
    : knots_(size_t(segments) + 1), cumulative_(size_t(segments) + 1, 0.0), segments_(segments),
      radiusMm_(radiusMm) {
  for (int k = 0; k <= segments; ++k) knots_[size_t(k)] = logKnots[size_t(k) * size_t(stride)];
  double h = radiusMm / segments;
  slope_.resize(size_t(segments));
  scale_.resize(size_t(segments));
  for (int k = 0; k < segments; ++k) {
    double y0 = knots_[size_t(k)];
    slope_[size_t(k)] = (knots_[size_t(k) + 1] - y0) / h;
    scale_[size_t(k)] = 2.0 * M_PI * std::exp(y0);
  }
  for (int k = 0; k < segments; ++k) cumulative_[size_t(k) + 1] = cumulative_[size_t(k)] + segmentEnergy(k, h);
}

double SegmentedProfile::segmentEnergy(int k, double length) const {
  // The integral of e^(y0 + beta u) 2 pi (a + u) du over u in [0, length].
  double h = radiusMm_ / segments_, a = k * h;
  double beta = slope_[size_t(k)];
  double x = beta * length, i0, i1;  // integrals of e^(beta u) and u e^(beta u)
  if (std::abs(x) < 1e-4) {
    i0 = length * (1.0 + x / 2.0 + x * x / 6.0);
    i1 = length * length * (0.5 + x / 3.0 + x * x / 8.0);
  } else {
    double ex = std::exp(x);  // one exponential for both (e^x - 1 loses 1e-12 of itself at x = 1e-4)
    double q = length / x;    // and one division
    i0 = q * (ex - 1.0);
    i1 = q * q * (ex * (x - 1.0) + 1.0);
  }
  return scale_[size_t(k)] * (a * i0 + i1);
}

double SegmentedProfile::value(double r) const {
  r = std::max(r, 0.0);
  if (r >= radiusMm_) return 0.0;
  double x = r / radiusMm_ * segments_;
  int k = std::min(int(x), segments_ - 1);
  double w = x - k;
  return std::exp(knots_[size_t(k)] * (1.0 - w) + knots_[size_t(k) + 1] * w);
}

double SegmentedProfile::energyWithin(double r) const {
  if (!(r > 0.0)) return 0.0;
  if (r >= radiusMm_) return cumulative_.back();
  double h = radiusMm_ / segments_;
  int k = std::min(int(r / h), segments_ - 1);
  return cumulative_[size_t(k)] + segmentEnergy(k, r - k * h);
}

// ---------------------------------------------------------------- fitting

namespace {

// ln P at r (mm) of one channel of a knot array (stride 3 between knots).
double logAt(const float* knots, int segments, double radiusMm, double r) {
  double x = std::clamp(r / radiusMm, 0.0, 1.0) * segments;
  int k = std::min(int(x), segments - 1);
  double w = x - k;
  return double(knots[3 * k]) * (1.0 - w) + double(knots[3 * (k + 1)]) * w;
}

// Relative energy error of a model profile against a source profile, channel
// c: the integral of |P_model - P_source| over that of P_source (both 2 pi r
// dr), by the trapezoid rule at `samples` points per source segment.
double energyError(const float* source, int sourceSegments, const float* model, int modelSegments,
                   double radiusMm, int c, int samples) {
  int count = sourceSegments * samples;
  double difference = 0.0, energy = 0.0;
  for (int i = 1; i <= count; ++i) {
    double r = radiusMm * i / count, w = i == count ? 0.5 : 1.0;
    double p = std::exp(logAt(source + c, sourceSegments, radiusMm, r));
    double q = std::exp(logAt(model + c, modelSegments, radiusMm, r));
    difference += w * r * std::abs(q - p);
    energy += w * r * p;
  }
  if (!(energy > 0.0)) return difference > 0.0 ? 1.0 : 0.0;
  return difference / energy;
}

double profileError(const float* source, int sourceSegments, const float* model, int modelSegments,
                    double radiusMm, int samples) {
  double e = 0.0;
  for (int c = 0; c < 3; ++c)
    e = std::max(e, energyError(source, sourceSegments, model, modelSegments, radiusMm, c, samples));
  return e;
}

// The same profile with n segments: ln P sampled at the new knots.
std::vector<float> resample(const float* knots, int segments, double radiusMm, int n) {
  std::vector<float> out(size_t(n + 1) * 3);
  for (int k = 0; k <= n; ++k)
    for (int c = 0; c < 3; ++c)
      out[size_t(k) * 3 + c] = float(logAt(knots + c, segments, radiusMm, radiusMm * k / n));
  return out;
}

// Clustering features: ln energy and ln mean radius per channel.
std::array<double, 6> features(const float* knots, int segments, double radiusMm) {
  std::array<double, 6> f{};
  for (int c = 0; c < 3; ++c) {
    double e = 0.0, m = 0.0;
    for (int k = 1; k <= segments; ++k) {
      double r = radiusMm * k / segments, w = k == segments ? 0.5 : 1.0;
      double p = w * r * std::exp(double(knots[3 * k + c]));
      e += p;
      m += p * r;
    }
    f[size_t(2 * c)] = std::log(e + 1e-300);
    f[size_t(2 * c + 1)] = std::log(m / std::max(e, 1e-300) + 1e-300);
  }
  return f;
}

double distance2(const std::array<double, 6>& a, const std::array<double, 6>& b) {
  double s = 0.0;
  for (size_t i = 0; i < 6; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

// Distinct source profiles, how many texels have each, and each texel's.
struct Distinct {
  std::vector<float> knots;       // distinct x (n + 1) x 3
  std::vector<uint32_t> counts;   // texels per distinct profile
  std::vector<uint32_t> ofTexel;  // distinct index per texel
  size_t size() const { return counts.size(); }
};

Distinct distinctProfiles(const float* logKnots, size_t texels, size_t stride) {
  Distinct d;
  d.ofTexel.resize(texels);
  std::unordered_multimap<uint64_t, uint32_t> byHash;
  size_t bytes = stride * sizeof(float);
  for (size_t t = 0; t < texels; ++t) {
    const float* p = logKnots + t * stride;
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    const unsigned char* b = reinterpret_cast<const unsigned char*>(p);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
    uint32_t found = UINT32_MAX;
    auto [lo, hi] = byHash.equal_range(h);
    for (auto it = lo; it != hi && found == UINT32_MAX; ++it)
      if (std::memcmp(d.knots.data() + size_t(it->second) * stride, p, bytes) == 0) found = it->second;
    if (found == UINT32_MAX) {
      found = uint32_t(d.counts.size());
      d.knots.insert(d.knots.end(), p, p + stride);
      d.counts.push_back(0);
      byHash.emplace(h, found);
    }
    ++d.counts[found];
    d.ofTexel[t] = found;
  }
  return d;
}

// Clusters the distinct profiles into at most k groups (k-means on the
// features, farthest-point start from the most common profile); returns the
// group of each distinct profile.
std::vector<uint32_t> cluster(const Distinct& d, const std::vector<std::array<double, 6>>& f, int k) {
  size_t n = d.size();
  std::vector<std::array<double, 6>> centres;
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  size_t first = size_t(std::max_element(d.counts.begin(), d.counts.end()) - d.counts.begin());
  centres.push_back(f[first]);
  while (int(centres.size()) < k) {
    size_t far = 0;
    for (size_t i = 0; i < n; ++i) {
      nearest[i] = std::min(nearest[i], distance2(f[i], centres.back()));
      if (nearest[i] > nearest[far]) far = i;
    }
    if (!(nearest[far] > 0.0)) break;
    centres.push_back(f[far]);
  }
  std::vector<uint32_t> group(n, 0);
  for (int iteration = 0; iteration < 10; ++iteration) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      uint32_t best = 0;
      double bestD = distance2(f[i], centres[0]);
      for (size_t c = 1; c < centres.size(); ++c) {
        double dc = distance2(f[i], centres[c]);
        if (dc < bestD) bestD = dc, best = uint32_t(c);
      }
      changed |= group[i] != best;
      group[i] = best;
    }
    if (!changed && iteration > 0) break;
    std::vector<std::array<double, 6>> sum(centres.size(), std::array<double, 6>{});
    std::vector<double> weight(centres.size(), 0.0);
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = 0; j < 6; ++j) sum[group[i]][j] += d.counts[i] * f[i][j];
      weight[group[i]] += d.counts[i];
    }
    for (size_t c = 0; c < centres.size(); ++c)
      if (weight[c] > 0)
        for (size_t j = 0; j < 6; ++j) centres[c][j] = sum[c][j] / weight[c];
  }
  return group;
}

// Distinct profiles whose errors are measured: all, or an even stride of
// kErrorSamples of them when there are more.
constexpr size_t kErrorSamples = 65536;
// fromDipoles: the media the model's error is measured on when it merged media.
constexpr size_t kMergeSamples = 512;

struct Fit {
  std::vector<float> palette;       // groups x (n + 1) x 3, source segments
  std::vector<uint32_t> groupOf;    // per distinct profile
  std::vector<uint32_t> counts;     // texels per group
  double meanError = 0.0, maxError = 0.0;
};

// The palette of a grouping: each group's count-weighted mean of ln P; and
// the texel-weighted error of the distinct profiles against their group's.
Fit paletteOf(const Distinct& d, std::vector<uint32_t> groupOf, size_t groups, int segments, double radiusMm) {
  size_t stride = size_t(segments + 1) * 3;
  Fit fit;
  fit.palette.assign(groups * stride, 0.0f);
  fit.counts.assign(groups, 0);
  std::vector<double> sum(groups * stride, 0.0);
  for (size_t i = 0; i < d.size(); ++i) {
    fit.counts[groupOf[i]] += d.counts[i];
    for (size_t j = 0; j < stride; ++j) sum[groupOf[i] * stride + j] += double(d.counts[i]) * d.knots[i * stride + j];
  }
  for (size_t g = 0; g < groups; ++g)
    for (size_t j = 0; j < stride; ++j)
      fit.palette[g * stride + j] = float(sum[g * stride + j] / std::max<uint32_t>(fit.counts[g], 1));
  size_t step = std::max<size_t>(1, d.size() / kErrorSamples);
  double weighted = 0.0, weights = 0.0;
  for (size_t i = 0; i < d.size(); i += step) {
    const float* p = d.knots.data() + i * stride;
    const float* q = fit.palette.data() + groupOf[i] * stride;
    double e = std::memcmp(p, q, stride * sizeof(float)) == 0 ? 0.0 : profileError(p, segments, q, segments, radiusMm, 1);
    weighted += e * d.counts[i];
    weights += d.counts[i];
    fit.maxError = std::max(fit.maxError, e);
  }
  fit.meanError = weights > 0 ? weighted / weights : 0.0;
  fit.groupOf = std::move(groupOf);
  return fit;
}

std::string texelName(size_t t, int width) {
  return "texel (" + std::to_string(t % size_t(width)) + ", " + std::to_string(t / size_t(width)) + ")";
}

// Every distinct profile's total (integral of P 2 pi r dr, per channel) at most maxTotal: more
// would send out more light than came in. The first texel of an offending profile is named; a
// profile whose ln P never goes below 0 over its whole radius is most likely P written as ln P.
void requireTotals(const Distinct& d, int segments, double radiusMm, double maxTotal, int width) {
  static const char* kChannels[3] = {"R", "G", "B"};
  size_t stride = size_t(segments + 1) * 3;
  for (size_t i = 0; i < d.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float* knots = d.knots.data() + i * stride + size_t(c);
      double total = SegmentedProfile(knots, segments, radiusMm, 3).totalEnergy();
      if (total <= maxTotal) continue;
      size_t texel = size_t(std::find(d.ofTexel.begin(), d.ofTexel.end(), uint32_t(i)) - d.ofTexel.begin());
      bool allPositive = true;
      for (int k = 0; k <= segments; ++k) allPositive = allPositive && knots[3 * k] >= 0.0f;
      std::ostringstream message;
      message << texelName(texel, width) << ": the " << kChannels[c] << " profile carries " << total
              << " of the light that enters (its integral of P 2 pi r dr), more than the " << maxTotal
              << " allowed: a profile cannot send out more light than came in"
              << (allPositive ? " (ln P is never below 0 over the whole radius: does the file hold P instead of ln P?)"
                              : "");
      fail(SS_INVALID_ARGUMENT, message.str());
    }
}

void requireSize(int width, int height, int segments, double radiusMm) {
  require(width >= 1 && height >= 1 && width <= ProfileSet::kMaxSide && height <= ProfileSet::kMaxSide,
          "profile map size must be in [1, " + std::to_string(ProfileSet::kMaxSide) + "] per side, got " +
              std::to_string(width) + " x " + std::to_string(height));
  require(segments >= 1 && segments <= ProfileSet::kMaxSegments,
          "segment count n must be in [1, " + std::to_string(ProfileSet::kMaxSegments) + "], got " +
              std::to_string(segments));
  require(std::isfinite(radiusMm) && radiusMm > 0.0 && radiusMm <= 1e6,
          "scattering radius r_s must be in (0, 1e6] mm, got " + std::to_string(radiusMm));
}

void requireKnots(const float* knots, size_t count, size_t stride, const std::function<std::string(size_t)>& name) {
  for (size_t i = 0; i < count; ++i)
    for (size_t j = 0; j < stride; ++j) {
      float v = knots[i * stride + j];
      if (!std::isfinite(v) || v > ProfileSet::kMaxLogValue || v < -1000.0f)
        fail(SS_INVALID_ARGUMENT, name(i) + ", knot " + std::to_string(j / 3) + ", channel " + "RGB"[j % 3] +
                                      ": ln P = " + std::to_string(v) + " is not a finite value in [-1000, " +
                                      std::to_string(int(ProfileSet::kMaxLogValue)) + "]");
    }
}

}  // namespace

// ---------------------------------------------------------------- ProfileSet

namespace {

// The model's error against the source, measured by the caller (fromDipoles, whose distinct
// profiles are merged media): given the palette (chosen segments) and the map, the mean and the
// largest error. Without one, the error is the fit's against the distinct profiles.
using SourceError = std::function<std::pair<double, double>(const std::vector<float>& palette, int segments,
                                                            const std::vector<uint16_t>& map)>;

ProfileSet build(const Distinct& d, int width, int height, int segments, double radiusMm, double tolerance,
                 const SourceError& sourceError = nullptr) {
  require(std::isfinite(tolerance) && tolerance >= 1e-6 && tolerance <= 1.0,
          "profile-fit tolerance must be in [1e-6, 1], got " + std::to_string(tolerance));
  size_t stride = size_t(segments + 1) * 3;

  // The tolerance is shared: half for clustering, half for fewer segments, so
  // that the model's error (their sum, reported) stays within it.
  double half = 0.5 * tolerance;

  // 1. Palette: the distinct profiles, or the fewest clusters that fit.
  Fit fit;
  if (d.size() <= size_t(ProfileSet::kMaxProfiles)) {
    std::vector<uint32_t> own(d.size());
    std::iota(own.begin(), own.end(), 0u);
    fit = paletteOf(d, std::move(own), d.size(), segments, radiusMm);
  } else {
    std::vector<std::array<double, 6>> f(d.size());
    for (size_t i = 0; i < d.size(); ++i) f[i] = features(d.knots.data() + i * stride, segments, radiusMm);
    for (int k = 8;; k *= 2) {
      k = std::min(k, ProfileSet::kMaxProfiles);
      std::vector<uint32_t> groups = cluster(d, f, k);
      size_t used = size_t(*std::max_element(groups.begin(), groups.end())) + 1;
      fit = paletteOf(d, std::move(groups), used, segments, radiusMm);
      if (fit.meanError <= half || k == ProfileSet::kMaxProfiles) break;
    }
  }
  // Most common first: entry 0 is what a mesh without UVs gets.
  size_t groups = fit.counts.size();
  std::vector<uint32_t> order(groups), rank(groups);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return fit.counts[a] > fit.counts[b]; });
  for (size_t i = 0; i < groups; ++i) rank[order[i]] = uint32_t(i);

  // 2. Segments: the fewest that keep every palette profile within tolerance.
  static const int kCandidates[] = {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512, 768};
  int chosen = segments;
  double segmentError = 0.0;
  for (int n : kCandidates) {
    if (n >= segments) break;
    double worst = 0.0;
    for (size_t g = 0; g < groups && worst <= half; ++g) {
      const float* p = fit.palette.data() + g * stride;
      std::vector<float> q = resample(p, segments, radiusMm, n);
      worst = std::max(worst, profileError(p, segments, q.data(), n, radiusMm, 4));
    }
    if (worst <= half) {
      chosen = n;
      segmentError = worst;
      break;
    }
  }
  std::vector<float> palette;
  palette.reserve(groups * size_t(chosen + 1) * 3);
  for (size_t i = 0; i < groups; ++i) {
    const float* p = fit.palette.data() + order[i] * stride;
    std::vector<float> q = chosen == segments ? std::vector<float>(p, p + stride) : resample(p, segments, radiusMm, chosen);
    palette.insert(palette.end(), q.begin(), q.end());
  }

  // 3. Map: one texel when every texel has the same profile.
  int mapWidth = groups == 1 ? 1 : width, mapHeight = groups == 1 ? 1 : height;
  std::vector<uint16_t> map(size_t(mapWidth) * mapHeight, 0);
  if (groups > 1)
    for (size_t t = 0; t < map.size(); ++t) map[t] = uint16_t(rank[fit.groupOf[d.ofTexel[t]]]);

  ProfileSetInfo info;
  info.segments = chosen;
  info.radiusMm = radiusMm;
  info.profiles = int(groups);
  info.width = mapWidth;
  info.height = mapHeight;
  info.fitError = fit.meanError + segmentError;
  info.maxFitError = fit.maxError + segmentError;
  if (sourceError) std::tie(info.fitError, info.maxFitError) = sourceError(palette, chosen, map);
  info.sourceSegments = segments;
  info.sourceProfiles = int(d.size());
  info.sourceWidth = width;
  info.sourceHeight = height;
  return ProfileSet::fromPalette(chosen, radiusMm, std::move(palette), mapWidth, mapHeight, std::move(map), info);
}

}  // namespace

ProfileSet ProfileSet::fromTexels(int width, int height, int segments, double radiusMm, const float* logKnots,
                                  double tolerance, double maxTotal) {
  requireSize(width, height, segments, radiusMm);
  require(logKnots != nullptr, "profile data is NULL");
  require(!std::isnan(maxTotal) && maxTotal > 0.0, "the most energy a profile may carry must be positive");
  size_t texels = size_t(width) * size_t(height), stride = size_t(segments + 1) * 3;
  require(uint64_t(texels) * stride <= kMaxSourceFloats,
          "profile data of " + std::to_string(width) + " x " + std::to_string(height) + " texels with " +
              std::to_string(segments) + " segments exceeds the 1 GiB budget");
  requireKnots(logKnots, texels, stride, [&](size_t t) { return texelName(t, width); });
  Distinct distinct = distinctProfiles(logKnots, texels, stride);
  if (std::isfinite(maxTotal)) requireTotals(distinct, segments, radiusMm, maxTotal, width);
  return build(distinct, width, height, segments, radiusMm, tolerance);
}

ProfileSet ProfileSet::fromDipoles(int width, int height, const float* sigmaA, const float* sigmaSPrime, double eta,
                                   double tolerance, int model) {
  require(model == kProfileDipole || model == kProfileTabulated, "unknown profile model " + std::to_string(model));
  requireSize(width, height, 1, 1.0);
  require(sigmaA != nullptr && sigmaSPrime != nullptr, "dipole coefficients are NULL");
  require(std::isfinite(eta) && eta >= 1.0 && eta <= 3.0, "eta must be in [1, 3], got " + std::to_string(eta));
  size_t texels = size_t(width) * size_t(height);
  // The distinct dipoles first: their profiles are what costs.
  std::vector<float> coefficients(texels * 6);
  for (size_t t = 0; t < texels; ++t)
    for (int c = 0; c < 3; ++c) {
      float a = sigmaA[3 * t + c], s = sigmaSPrime[3 * t + c];
      if (!(std::isfinite(a) && a > 0.0f && a <= 1e4f) || !(std::isfinite(s) && s >= 0.0f && s <= 1e4f))
        fail(SS_INVALID_ARGUMENT, texelName(t, width) + ": sigma_a must be in (0, 1e4] and sigma_s' in [0, 1e4] per mm, "
                                      "got " + std::to_string(a) + " and " + std::to_string(s));
      coefficients[6 * t + size_t(c)] = a;
      coefficients[6 * t + 3 + size_t(c)] = s;
    }
  Distinct dipoles = distinctProfiles(coefficients.data(), texels, 6);
  // More media than kMaxMedia (a painted texture holds tens of thousands): merged on a grid in
  // ln sigma, the step grown by 1.25 until at most kMaxMedia cells hold media, each cell the count-weighted
  // mean of its media in ln sigma. The palette keeps kMaxProfiles anyway; the model's error is then
  // measured against a sample of the media themselves (below).
  Distinct media = dipoles;
  if (dipoles.size() > size_t(kMaxMedia)) {
    std::vector<double> ln(dipoles.size() * 6);
    for (size_t i = 0; i < ln.size(); ++i) ln[i] = std::log(std::max(double(dipoles.knots[i]), 1e-6));
    auto lnSigma = [&](size_t i, int j) { return ln[6 * i + size_t(j)]; };
    std::vector<uint32_t> cellOf(dipoles.size());
    size_t cells = 0;
    for (double step = 1.0 / 256.0;; step *= 1.25) {
      std::unordered_map<uint64_t, std::vector<std::pair<std::array<int64_t, 6>, uint32_t>>> index;
      cells = 0;
      for (size_t i = 0; i < dipoles.size(); ++i) {
        std::array<int64_t, 6> key;
        uint64_t h = 1469598103934665603ull;
        for (int j = 0; j < 6; ++j) {
          key[size_t(j)] = int64_t(std::floor(lnSigma(i, j) / step));
          h = (h ^ uint64_t(key[size_t(j)])) * 1099511628211ull;
        }
        auto& bucket = index[h];
        auto found = std::find_if(bucket.begin(), bucket.end(), [&](const auto& e) { return e.first == key; });
        if (found == bucket.end()) bucket.emplace_back(key, uint32_t(cells++)), found = bucket.end() - 1;
        cellOf[i] = found->second;
      }
      if (cells <= size_t(kMaxMedia)) break;
    }
    std::vector<double> sum(cells * 6, 0.0);
    media.counts.assign(cells, 0);
    for (size_t i = 0; i < dipoles.size(); ++i) {
      media.counts[cellOf[i]] += dipoles.counts[i];
      for (int j = 0; j < 6; ++j) sum[cellOf[i] * 6 + size_t(j)] += dipoles.counts[i] * lnSigma(i, j);
    }
    media.knots.assign(cells * 6, 0.0f);
    for (size_t c = 0; c < cells; ++c)
      for (int j = 0; j < 6; ++j) media.knots[c * 6 + size_t(j)] = float(std::exp(sum[c * 6 + size_t(j)] / media.counts[c]));
    for (uint32_t& m : media.ofTexel) m = cellOf[m];
  }
  // One r_s for all: the longest 99.9 % radius. Segments: a quarter of the
  // shortest z_r, where the dipole bends (fitting then keeps what is needed).
  auto modelsOf = [&](const float* k) {
    return std::array<std::shared_ptr<const RadialProfile>, 3>{makeMediumProfile({k[0], k[3], eta}, model),
                                                                makeMediumProfile({k[1], k[4], eta}, model),
                                                                makeMediumProfile({k[2], k[5], eta}, model)};
  };
  std::vector<std::array<std::shared_ptr<const RadialProfile>, 3>> models(media.size());
  std::vector<double> radii(media.size(), 0.0), scales(media.size(), std::numeric_limits<double>::infinity());
  parallelFor(media.size(), 64, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      models[i] = modelsOf(media.knots.data() + 6 * i);
      for (const auto& m : models[i]) {
        radii[i] = std::max(radii[i], m->radiusForEnergy(0.999));
        scales[i] = std::min(scales[i], m->scaleHint());  // z_r = 1 / sigma_t' for either model
      }
    }
  }, nullptr, 0.0, 1.0);
  double radiusMm = double(float(*std::max_element(radii.begin(), radii.end())));  // as files and the API hold it
  double zr = *std::min_element(scales.begin(), scales.end());
  int segments = std::clamp(int(std::ceil(radiusMm / (0.25 * zr))), 16, kMaxSegments);
  size_t stride = size_t(segments + 1) * 3;
  require(uint64_t(media.size()) * stride <= kMaxSourceFloats,
          std::to_string(media.size()) + " different dipoles with " + std::to_string(segments) +
              " segments exceed the 1 GiB budget; use fewer distinct values");
  // ln P at the knots, keeping the model's total reflectance (the tail beyond r_s is cut).
  auto knotsOf = [&](const std::array<std::shared_ptr<const RadialProfile>, 3>& channels, float* knots) {
    for (int c = 0; c < 3; ++c) {
      const RadialProfile& m = *channels[size_t(c)];
      float* out = knots + size_t(c);
      for (int k = 0; k <= segments; ++k)
        out[3 * k] = float(std::max(std::log(m.value(radiusMm * k / segments)), -1000.0));
      double kept = SegmentedProfile(out, segments, radiusMm, 3).totalEnergy();
      double shift = kept > 0.0 ? std::log(m.totalEnergy() / kept) : 0.0;
      for (int k = 0; k <= segments; ++k) out[3 * k] = float(std::max(double(out[3 * k]) + shift, -1000.0));
    }
  };
  Distinct d;
  d.counts = media.counts;
  d.ofTexel = std::move(media.ofTexel);
  d.knots.resize(media.size() * stride);
  parallelFor(media.size(), 64, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) knotsOf(models[i], d.knots.data() + i * stride);
  }, nullptr, 0.0, 1.0);
  // Merged: the model's error is measured against the media themselves, each sampled medium's
  // profile against its palette entry, on an even stride of at most kMergeSamples media, weighted
  // by texels (the fit's own error is against the merged cells).
  SourceError sourceError;
  if (media.size() < dipoles.size())
    sourceError = [&](const std::vector<float>& palette, int chosen, const std::vector<uint16_t>& map) {
      size_t step = std::max<size_t>(1, dipoles.size() / kMergeSamples), samples = (dipoles.size() + step - 1) / step;
      std::vector<size_t> texelOf(dipoles.size(), 0);
      for (size_t t = texels; t-- > 0;) texelOf[dipoles.ofTexel[t]] = t;
      std::vector<double> errors(samples, 0.0);
      parallelFor(samples, 16, [&](size_t begin, size_t end) {
        std::vector<float> own(stride);
        for (size_t k = begin; k < end; ++k) {
          size_t i = k * step;
          knotsOf(modelsOf(dipoles.knots.data() + 6 * i), own.data());
          size_t entry = map.size() == 1 ? 0 : map[texelOf[i]];
          errors[k] = profileError(own.data(), segments, palette.data() + entry * size_t(chosen + 1) * 3, chosen,
                                   radiusMm, 1);
        }
      }, nullptr, 0.0, 1.0);
      double mean = 0.0, largest = 0.0, weights = 0.0;
      for (size_t k = 0; k < samples; ++k) {
        mean += errors[k] * dipoles.counts[k * step];
        weights += dipoles.counts[k * step];
        largest = std::max(largest, errors[k]);
      }
      return std::pair{mean / weights, largest};
    };
  return build(d, width, height, segments, radiusMm, tolerance, sourceError);
}

ProfileSet ProfileSet::fromPalette(int segments, double radiusMm, std::vector<float> palette, int width, int height,
                                   std::vector<uint16_t> map, const ProfileSetInfo& info) {
  requireSize(width, height, segments, radiusMm);
  size_t stride = size_t(segments + 1) * 3;
  require(!palette.empty() && palette.size() % stride == 0 && palette.size() / stride <= size_t(kMaxProfiles),
          "a profile palette holds 1 to " + std::to_string(kMaxProfiles) + " profiles of " + std::to_string(stride) +
              " values, got " + std::to_string(palette.size()) + " values");
  size_t profiles = palette.size() / stride;
  requireKnots(palette.data(), profiles, stride, [](size_t i) { return "profile " + std::to_string(i); });
  require(map.size() == size_t(width) * size_t(height), "profile map holds " + std::to_string(map.size()) +
                                                            " texels, not " + std::to_string(width) + " x " +
                                                            std::to_string(height));
  ProfileSet set;
  set.counts_.assign(profiles, 0);
  for (uint16_t i : map) {
    require(i < profiles, "profile map index " + std::to_string(i) + " is out of range (" +
                              std::to_string(profiles) + " profiles)");
    ++set.counts_[i];
  }
  set.palette_ = std::move(palette);
  set.map_ = std::move(map);
  set.info_ = info;
  set.info_.segments = segments;
  set.info_.radiusMm = radiusMm;
  set.info_.profiles = int(profiles);
  set.info_.width = width;
  set.info_.height = height;
  return set;
}

int ProfileSet::profileAt(float u, float v) const {
  auto texel = [](float t, int size) {
    float f = t - std::floor(t);
    return std::clamp(int(f * float(size)), 0, size - 1);
  };
  if (!std::isfinite(u) || !std::isfinite(v)) return map_[0];
  return map_[size_t(texel(v, height())) * size_t(width()) + size_t(texel(u, width()))];
}

SegmentedProfile ProfileSet::channel(int index, int c) const {
  return SegmentedProfile(profile(index) + c, segments(), radiusMm(), 3);
}

std::vector<std::shared_ptr<const SplatKernel>> ProfileSet::kernels(double mmPerUnit) const {
  std::lock_guard<std::mutex> lock(kernelCache_->mutex);
  if (kernelCache_->mmPerUnit == mmPerUnit && !kernelCache_->kernels.empty()) return kernelCache_->kernels;
  std::vector<std::shared_ptr<const SplatKernel>> built(static_cast<size_t>(profileCount()));
  parallelFor(built.size(), 1, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      SplatKernel::Channels channels;
      for (int c = 0; c < 3; ++c) channels[size_t(c)] = std::make_shared<SegmentedProfile>(channel(int(i), c));
      built[i] = std::make_shared<const SplatKernel>(std::move(channels), mmPerUnit);
    }
  }, [](double) { return true; }, 0.0, 1.0);
  kernelCache_->mmPerUnit = mmPerUnit;
  kernelCache_->kernels = built;
  return built;
}

std::vector<float> ProfileSet::texels() const {
  size_t s = size_t(stride());
  std::vector<float> out(map_.size() * s);
  for (size_t t = 0; t < map_.size(); ++t) std::copy_n(profile(map_[t]), s, out.data() + t * s);
  return out;
}

}  // namespace subsplat
