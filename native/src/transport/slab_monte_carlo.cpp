#include "transport/slab_monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

#include "util/error.h"

namespace subsplat {

double exponentialIntegral(int n, double x) {
  require(n >= 1 && x >= 0.0 && !(n == 1 && x == 0.0), "E_n(x): n >= 1, x >= 0 (x > 0 for n = 1)");
  const double euler = 0.5772156649015329, eps = 1e-16;
  if (std::isinf(x)) return 0.0;
  if (x == 0.0) return 1.0 / (n - 1);
  if (x > 1.0) {
    // Continued fraction (modified Lentz; Numerical Recipes 6.3).
    double b = x + n, c = 1e300, d = 1.0 / b, h = d;
    for (int i = 1; i < 1000; ++i) {
      double a = -static_cast<double>(i) * (n - 1 + i);
      b += 2.0;
      d = 1.0 / (a * d + b);
      c = b + a / c;
      double step = c * d;
      h *= step;
      if (std::abs(step - 1.0) < eps) break;
    }
    return h * std::exp(-x);
  }
  // Power series.
  int nm1 = n - 1;
  double sum = nm1 != 0 ? 1.0 / nm1 : -std::log(x) - euler, factor = 1.0;
  for (int i = 1; i < 1000; ++i) {
    factor *= -x / i;
    double term;
    if (i != nm1) {
      term = -factor / (i - nm1);
    } else {
      double psi = -euler;
      for (int k = 1; k <= nm1; ++k) psi += 1.0 / k;
      term = factor * (-std::log(x) + psi);
    }
    sum += term;
    if (std::abs(term) < std::abs(sum) * eps) break;
  }
  return sum;
}

double slabUnscatteredTransmittance(const SlabSettings& s) {
  if (std::isinf(s.thickness)) return 0.0;
  if (s.incidence == SlabIncidence::Collimated) return std::exp(-s.thickness / s.mu0);
  return 2.0 * exponentialIntegral(3, s.thickness);
}

double SlabTallies::fraction(uint64_t count) const {
  return collided * static_cast<double>(count) / static_cast<double>(settings.paths);
}

double SlabTallies::standardError(uint64_t count) const {
  double n = static_cast<double>(settings.paths), p = static_cast<double>(count) / n;
  return collided * std::sqrt(p * (1.0 - p) / n);
}

double SlabTallies::radianceInCosineBin(const std::vector<uint64_t>& bins, int i) const {
  double lo = static_cast<double>(i) / settings.cosineBins, hi = static_cast<double>(i + 1) / settings.cosineBins;
  return fraction(bins.at(i)) / (M_PI * (hi * hi - lo * lo));
}

double SlabTallies::exitanceInRadiusBin(const std::vector<uint64_t>& bins, int i) const {
  double lo = settings.radiusEdges.at(i), hi = settings.radiusEdges.at(i + 1);
  return fraction(bins.at(i)) / (M_PI * (hi * hi - lo * lo));
}

namespace {

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// xoshiro256** (Blackman and Vigna), one per path, seeded by splitmix64 from (seed, path).
class PathRandom {
 public:
  PathRandom(uint64_t seed, uint64_t path) {
    uint64_t state = seed;
    state = splitmix64(state) ^ path;
    for (uint64_t& word : s_) word = splitmix64(state);
  }
  // Uniform in [0, 1), 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t next() {
    uint64_t result = rotl(s_[1] * 5, 7) * 9, t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  uint64_t s_[4];
};

void resizeBins(SlabTallies& t) {
  size_t c = static_cast<size_t>(t.settings.cosineBins);
  size_t r = t.settings.radiusEdges.empty() ? 0 : t.settings.radiusEdges.size() - 1;
  for (auto* bins : {&t.reflectedByCosine, &t.transmittedByCosine, &t.reflectedOnceByCosine, &t.transmittedOnceByCosine})
    bins->assign(c, 0);
  for (auto* bins : {&t.reflectedByRadius, &t.transmittedByRadius, &t.reflectedOnceByRadius, &t.transmittedOnceByRadius})
    bins->assign(r, 0);
}

void addBins(std::vector<uint64_t>& into, const std::vector<uint64_t>& from) {
  for (size_t i = 0; i < into.size(); ++i) into[i] += from[i];
}

// Paths [begin, end) into t (whose bins are sized).
void tracePaths(const SlabSettings& s, double collided, uint64_t begin, uint64_t end, SlabTallies& t) {
  const double tau = s.thickness, a = s.albedo;
  const bool radial = !s.radiusEdges.empty(), collimated = s.incidence == SlabIncidence::Collimated;
  const int cosineBins = s.cosineBins;
  for (uint64_t path = begin; path < end; ++path) {
    PathRandom random(s.seed, path);
    // Incidence, and the first collision drawn within the slab (optical path l < tau / mu0).
    double mu0 = s.mu0, reach = collided;  // reach: 1 - exp(-tau / mu0), the chance to collide
    if (!collimated) {
      // Cosine-weighted incidence, kept with probability 1 - exp(-tau / mu0) (the collided share).
      for (;;) {
        mu0 = std::sqrt(1.0 - random.uniform());
        reach = std::isinf(tau) ? 1.0 : -std::expm1(-tau / mu0);
        if (random.uniform() < reach) break;
      }
    }
    double l = -std::log1p(-random.uniform() * reach);
    double z = l * mu0, x = 0.0, y = 0.0;
    if (radial) x = l * std::sqrt(std::max(0.0, 1.0 - mu0 * mu0));
    uint64_t collisions = 0;
    for (;;) {
      ++collisions;
      // Absorbed with probability 1 - a; otherwise scattered isotropically.
      if (random.uniform() >= a) {
        ++t.absorbed;
        break;
      }
      if (collisions > s.maxCollisions) {
        ++t.truncated;
        break;
      }
      double w = 2.0 * random.uniform() - 1.0;  // direction cosine along +z (into the slab)
      double phi = 2.0 * M_PI * random.uniform();
      double flight = -std::log1p(-random.uniform());
      double zNext = z + flight * w;
      bool up = zNext < 0.0, down = zNext > tau;
      if (!up && !down) {
        if (radial) {
          double horizontal = flight * std::sqrt(std::max(0.0, 1.0 - w * w));
          x += horizontal * std::cos(phi);
          y += horizontal * std::sin(phi);
        }
        z = zNext;
        continue;
      }
      // Left through a face: tally the exit cosine and where it crossed the face.
      bool once = collisions == 1;
      double mu = std::abs(w);
      if (up) {
        ++t.reflected;
        if (once) ++t.reflectedOnce;
      } else {
        ++t.transmitted;
        if (once) ++t.transmittedOnce;
      }
      if (cosineBins > 0) {
        int bin = std::min(static_cast<int>(mu * cosineBins), cosineBins - 1);
        ++(up ? t.reflectedByCosine : t.transmittedByCosine)[bin];
        if (once) ++(up ? t.reflectedOnceByCosine : t.transmittedOnceByCosine)[bin];
      }
      if (radial) {
        double toFace = (up ? -z : tau - z) / w;  // distance along the flight to the face
        double horizontal = toFace * std::sqrt(std::max(0.0, 1.0 - w * w));
        double xe = x + horizontal * std::cos(phi), ye = y + horizontal * std::sin(phi);
        double r = std::sqrt(xe * xe + ye * ye);
        const std::vector<double>& edges = s.radiusEdges;
        if (r >= edges.front() && r < edges.back()) {
          size_t bin = static_cast<size_t>(std::upper_bound(edges.begin(), edges.end(), r) - edges.begin()) - 1;
          ++(up ? t.reflectedByRadius : t.transmittedByRadius)[bin];
          if (once) ++(up ? t.reflectedOnceByRadius : t.transmittedOnceByRadius)[bin];
        }
      }
      break;
    }
  }
}

}  // namespace

SlabTallies simulateSlab(const SlabSettings& s) {
  require(s.albedo >= 0.0 && s.albedo <= 1.0, "slab: albedo " + std::to_string(s.albedo) + " outside [0, 1]");
  require(s.thickness > 0.0, "slab: thickness must be positive (infinity: half-space)");
  require(s.incidence == SlabIncidence::Diffuse || (s.mu0 > 0.0 && s.mu0 <= 1.0), "slab: mu0 outside (0, 1]");
  require(s.paths > 0, "slab: at least one path");
  require(s.cosineBins >= 0 && s.cosineBins <= 1000000, "slab: cosine bins outside [0, 1e6]");
  require(s.radiusEdges.empty() || s.radiusEdges.size() >= 2, "slab: radius edges: none, or at least two");
  for (size_t i = 0; i < s.radiusEdges.size(); ++i)
    require(std::isfinite(s.radiusEdges[i]) && s.radiusEdges[i] >= 0.0 && (i == 0 || s.radiusEdges[i] > s.radiusEdges[i - 1]),
            "slab: radius edges must be finite, >= 0 and increasing");
  require(s.threads >= 1 && s.threads <= 1024, "slab: threads outside [1, 1024]");

  SlabTallies total;
  total.settings = s;
  total.unscattered = slabUnscatteredTransmittance(s);
  // 1 - unscattered, without the cancellation of thin slabs where it can be avoided.
  bool thinBeam = s.incidence == SlabIncidence::Collimated && !std::isinf(s.thickness);
  total.collided = thinBeam ? -std::expm1(-s.thickness / s.mu0) : 1.0 - total.unscattered;
  resizeBins(total);
  require(total.collided > 0.0, "slab: too thin for any light to collide");

  uint64_t threads = std::min<uint64_t>(static_cast<uint64_t>(s.threads), s.paths);
  std::vector<SlabTallies> parts(threads, total);
  std::vector<std::thread> workers;
  for (uint64_t k = 0; k < threads; ++k) {
    uint64_t begin = s.paths * k / threads, end = s.paths * (k + 1) / threads;
    if (threads == 1)
      tracePaths(s, total.collided, begin, end, parts[k]);
    else
      workers.emplace_back([&, k, begin, end] { tracePaths(s, total.collided, begin, end, parts[k]); });
  }
  for (std::thread& w : workers) w.join();
  for (const SlabTallies& p : parts) {
    total.reflected += p.reflected;
    total.transmitted += p.transmitted;
    total.absorbed += p.absorbed;
    total.truncated += p.truncated;
    total.reflectedOnce += p.reflectedOnce;
    total.transmittedOnce += p.transmittedOnce;
    addBins(total.reflectedByCosine, p.reflectedByCosine);
    addBins(total.transmittedByCosine, p.transmittedByCosine);
    addBins(total.reflectedOnceByCosine, p.reflectedOnceByCosine);
    addBins(total.transmittedOnceByCosine, p.transmittedOnceByCosine);
    addBins(total.reflectedByRadius, p.reflectedByRadius);
    addBins(total.transmittedByRadius, p.transmittedByRadius);
    addBins(total.reflectedOnceByRadius, p.reflectedOnceByRadius);
    addBins(total.transmittedOnceByRadius, p.transmittedOnceByRadius);
  }
  return total;
}

}  // namespace subsplat
