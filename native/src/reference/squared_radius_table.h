// A radial function of three channels tabulated against the squared radius, for REFERENCE's inner
// loop (some 10^8 kernel evaluations a frame): a value is read with no logarithm and no
// exponential. The node below r^2 is found from the float's exponent and its top mantissa bits
// (kNodesPerOctave nodes per octave of r^2, evenly spaced within it), and the value is linear in
// r^2 between that node and the next. Relative to a smooth function, between nodes a power law
// r^-q is off by about q (q + 2) / 32 / kNodesPerOctave^2 (1.4e-6 for q = 1, the once-scattered
// peak) and exp(-r / l) by (r / l / kNodesPerOctave)^2 / 32 (2.3e-5 at r = 7 l, where it is 1e-3 of
// its value at r = 0). The TABULATED profile is power laws that meet at kinks (its table's bins),
// and across a kink the line between two nodes is off by up to 1.2e-3 on the measured media, over a
// 1/512 of the radius; in energy the table is the profile within 1e-5
// (ReferenceTable.AgreesWithTheProfileItTabulates, every preset at three scene scales).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "material/transport_model.h"

namespace subsplat {

class SquaredRadiusTable {
 public:
  static constexpr int kBits = 8;
  static constexpr int kNodesPerOctave = 1 << kBits;

  SquaredRadiusTable() = default;
  // value(r2, c): channel c at r2 (r2 > 0). The table spans whole octaves of r^2 from the one
  // holding r2Lo to the one past r2Hi (0 < r2Lo < r2Hi); below its first node every channel holds
  // its value there (where the caller's function is constant), from its last node on it is 0
  // (where the caller's function is nothing).
  template <class F>
  SquaredRadiusTable(double r2Lo, double r2Hi, F value) {
    int lo = int(std::floor(std::log2(r2Lo))), hi = int(std::ceil(std::log2(r2Hi))) + 1;
    first_ = bits(std::ldexp(1.0f, lo)) >> kShift;
    nodes_ = (hi - lo) * kNodesPerOctave + 1;
    values_.resize(size_t(nodes_) * 3);
    for (int i = 0; i < nodes_; ++i) {
      double r2 = std::ldexp(1.0 + double(i % kNodesPerOctave) / kNodesPerOctave, lo + i / kNodesPerOctave);
      for (int c = 0; c < 3; ++c) values_[size_t(i) * 3 + size_t(c)] = float(value(r2, c));
    }
    for (int c = 0; c < 3; ++c) values_[size_t(nodes_ - 1) * 3 + size_t(c)] = 0.0f;
  }

  double value(double r2, int c) const { return at(nodeOf(r2), c); }
  // The three channels at one r2: the node found once.
  void values(double r2, double out[3]) const {
    const Node n = nodeOf(r2);
    for (int c = 0; c < 3; ++c) out[c] = at(n, c);
  }

 private:
  // The node below r2 (i < 0 below the first node, also for a negative r2; i >= nodes_ - 1 from the
  // last on) and the fraction t of the way to the next.
  struct Node {
    int64_t i;
    float t;
  };
  Node nodeOf(double r2) const {
    uint32_t b = bits(float(r2));
    if ((b >> 31) != 0) return {-1, 0.0f};
    return {int64_t(b >> kShift) - int64_t(first_), float(b & kFraction) * (1.0f / float(kFraction + 1))};
  }
  double at(const Node& n, int c) const {
    if (n.i < 0) return values_[size_t(c)];
    if (n.i >= nodes_ - 1) return 0.0;
    const float* v = &values_[size_t(n.i) * 3 + size_t(c)];
    return double(v[0] + n.t * (v[3] - v[0]));
  }
  static constexpr int kShift = 23 - kBits;  // float: 23 mantissa bits
  static constexpr uint32_t kFraction = (1u << kShift) - 1;
  static uint32_t bits(float f) {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
  }
  uint32_t first_ = 0;
  int nodes_ = 0;
  std::vector<float> values_;  // node-major, three channels
};

// REFERENCE's table of the TABULATED model's three channels in a scene of mmPerUnit millimetres per
// unit: P in 1 / unit^2 against r^2 in unit^2.
inline SquaredRadiusTable tabulate(const std::vector<std::shared_ptr<const TabulatedProfile>>& channels, double mmPerUnit) {
  double inner = HUGE_VAL, outer = 0.0;  // mm: every channel is constant within, nothing beyond
  for (const auto& p : channels) inner = std::min(inner, p->innerRadius()), outer = std::max(outer, p->outerRadius());
  const double perUnit2 = mmPerUnit * mmPerUnit, lnMmPerUnit = std::log(mmPerUnit);
  return SquaredRadiusTable(inner * inner / perUnit2, outer * outer / perUnit2, [&](double r2, int c) {
    return channels[size_t(c)]->valueAtLog(0.5 * std::log(r2) + lnMmPerUnit) * perUnit2;
  });
}

}  // namespace subsplat
