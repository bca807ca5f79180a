#include "transport/adding_doubling.h"

#include <cmath>
#include <string>
#include <utility>

#include "transport/hfunction.h"
#include "util/error.h"

namespace subsplat {

namespace {

// Dense m x m matrices, row major: M[i * m + j] maps incoming node j to outgoing node i.
using Matrix = std::vector<double>;

Matrix multiply(const Matrix& a, const Matrix& b, int m) {
  Matrix c(m * m, 0.0);
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < m; ++k) {
      double f = a[i * m + k];
      if (f == 0.0) continue;
      for (int j = 0; j < m; ++j) c[i * m + j] += f * b[k * m + j];
    }
  return c;
}

// (I - a)^-1 by Gauss-Jordan with partial pivoting.
Matrix inverseOfIdentityMinus(const Matrix& a, int m) {
  Matrix left(m * m), right(m * m, 0.0);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) left[i * m + j] = (i == j ? 1.0 : 0.0) - a[i * m + j];
    right[i * m + i] = 1.0;
  }
  for (int c = 0; c < m; ++c) {
    int pivot = c;
    for (int r = c + 1; r < m; ++r)
      if (std::abs(left[r * m + c]) > std::abs(left[pivot * m + c])) pivot = r;
    if (pivot != c)
      for (int k = 0; k < m; ++k) {
        std::swap(left[c * m + k], left[pivot * m + k]);
        std::swap(right[c * m + k], right[pivot * m + k]);
      }
    double p = left[c * m + c];
    for (int k = 0; k < m; ++k) {
      left[c * m + k] /= p;
      right[c * m + k] /= p;
    }
    for (int r = 0; r < m; ++r) {
      if (r == c) continue;
      double f = left[r * m + c];
      if (f == 0.0) continue;
      for (int k = 0; k < m; ++k) {
        left[r * m + k] -= f * left[c * m + k];
        right[r * m + k] -= f * right[c * m + k];
      }
    }
  }
  return right;
}

}  // namespace

SlabSolution solveSlabByAddingDoubling(double albedo, double thickness, double mu0, int nodes) {
  require(albedo >= 0.0 && albedo <= 1.0, "adding-doubling: albedo " + std::to_string(albedo) + " outside [0, 1]");
  require(std::isfinite(thickness) && thickness > 0.0, "adding-doubling: thickness must be finite and positive");
  require(mu0 > 0.0 && mu0 <= 1.0, "adding-doubling: mu0 outside (0, 1]");
  require(nodes >= 2 && nodes <= 512, "adding-doubling: nodes outside [2, 512]");

  // Node 0: the beam (weight 0); nodes 1..n: the quadrature.
  MuQuadrature q = gaussLegendreInSqrtMu(nodes);
  int m = nodes + 1;
  std::vector<double> mu(m), w(m);
  mu[0] = mu0;
  w[0] = 0.0;
  for (int i = 0; i < nodes; ++i) {
    mu[i + 1] = q.mu[i];
    w[i + 1] = q.weight[i];
  }

  // The thinnest layer: thickness / 2^k <= 1e-9.
  int doublings = 0;
  double layer = thickness;
  while (layer > 1e-9) {
    layer *= 0.5;
    ++doublings;
  }

  // Its exact single scattering, as flux from node j into node i: a beam of irradiance 1 at mu_j
  // gives radiance a (1 - e^{-t (1/mu_j + 1/mu_i)}) / (4 pi (mu_j + mu_i)) reflected and
  // a (e^{-t/mu_i} - e^{-t/mu_j}) / (4 pi (mu_i - mu_j)) transmitted; flux is 2 pi mu_i w_i times that.
  Matrix r(m * m), t(m * m);  // t: scattered transmission only
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      double into = 0.5 * albedo * w[i] * mu[i];
      r[i * m + j] = into * -std::expm1(-layer * (1.0 / mu[j] + 1.0 / mu[i])) / (mu[j] + mu[i]);
      double gap = mu[i] - mu[j];
      // (e^{-t/mu_i} - e^{-t/mu_j}) / (mu_i - mu_j), written without cancellation:
      // e^{-t/mu_j} (e^{t (1/mu_j - 1/mu_i)} - 1) / gap = e^{-t/mu_j} expm1(t gap / (mu_i mu_j)) / gap.
      double ratio = std::abs(gap) < 1e-300 ? layer / (mu[i] * mu[i]) * std::exp(-layer / mu[i])
                                          : std::exp(-layer / mu[j]) * std::expm1(layer * gap / (mu[i] * mu[j])) / gap;
      t[i * m + j] = into * ratio;
    }
  // The quadrature of these columns misses a little near mu = 0 (they change over mu ~ t there):
  // scale each so that the layer sends out all it scatters once, a (1 - e^{-t/mu_j}), so that at
  // a = 1 nothing is lost. (What it misses, light scattered twice within 1e-9, is below 1e-9.)
  for (int j = 0; j < m; ++j) {
    double out = 0.0;
    for (int i = 0; i < m; ++i) out += r[i * m + j] + t[i * m + j];
    double scale = out > 0.0 ? albedo * -std::expm1(-layer / mu[j]) / out : 0.0;
    for (int i = 0; i < m; ++i) {
      r[i * m + j] *= scale;
      t[i * m + j] *= scale;
    }
  }
  // Unscattered light keeps its direction: T = D + diag(e), D the scattered part. They are kept
  // apart, and (I - R R)^-1 as I + B, so that no small quantity is the difference of two near 1
  // (e is 1 - 1e-9 in the thinnest layer; its loss would keep only 7 digits).
  Matrix d = std::move(t);
  std::vector<double> e(m);
  for (int i = 0; i < m; ++i) e[i] = std::exp(-layer / mu[i]);
  auto leftT = [&](const Matrix& x) {  // T x
    Matrix y = multiply(d, x, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) y[i * m + j] += e[i] * x[i * m + j];
    return y;
  };
  auto rightT = [&](const Matrix& x) {  // x T
    Matrix y = multiply(x, d, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) y[i * m + j] += x[i * m + j] * e[j];
    return y;
  };

  for (int k = 0; k < doublings; ++k) {
    // B = (I - R R)^-1 R R: light that went back and forth between the halves.
    Matrix rr = multiply(r, r, m);
    Matrix b = multiply(inverseOfIdentityMinus(rr, m), rr, m);
    Matrix tb = leftT(b);
    // R' = R + T R T + T B R T;  D' = T T - diag(e^2) + T B T.
    Matrix rt = rightT(r);
    Matrix rNext = leftT(rt);
    Matrix tbrt = multiply(tb, rt, m);
    Matrix dNext = multiply(d, d, m), tbt = rightT(tb);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        int ij = i * m + j;
        rNext[ij] += r[ij] + tbrt[ij];
        dNext[ij] += d[ij] * (e[i] + e[j]) + tbt[ij];
      }
    r = std::move(rNext);
    d = std::move(dNext);
    // e of the doubled layer from exp, not e^2: squaring 30 times and more would grow e's
    // rounding 2^k-fold, and with it the energy the slab seems to lose (1e-7 at tau = 16).
    layer *= 2.0;
    for (int i = 0; i < m; ++i) e[i] = std::exp(-layer / mu[i]);
  }
  SlabSolution s;
  s.unscatteredTransmittance = std::exp(-thickness / mu0);
  s.mu.assign(mu.begin() + 1, mu.end());
  for (int i = 1; i < m; ++i) {
    // Column 0: the beam. Node 0 has weight 0, so no scattered light flows into it.
    s.reflectance += r[i * m + 0];
    s.scatteredTransmittance += d[i * m + 0];
    double perRadiance = 2.0 * M_PI * mu[i] * w[i];
    s.reflectedRadiance.push_back(r[i * m + 0] / perRadiance);
    s.transmittedRadiance.push_back(d[i * m + 0] / perRadiance);
    // Uniform radiance: irradiance pi, flux 2 pi mu_j w_j into node j, so a weight 2 mu_j w_j.
    for (int j = 1; j < m; ++j) {
      s.diffuseReflectance += r[i * m + j] * 2.0 * mu[j] * w[j];
      s.diffuseTransmittance += d[i * m + j] * 2.0 * mu[j] * w[j];
    }
    s.diffuseTransmittance += e[i] * 2.0 * mu[i] * w[i];  // unscattered: 2 E_3(tau) by the quadrature
  }
  return s;
}

}  // namespace subsplat
