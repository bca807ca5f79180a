#include "transport/hfunction.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "util/error.h"

namespace subsplat {

void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  require(n >= 1, "Gauss-Legendre: at least one node");
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Newton on P_n from the Tricomi estimate of the i-th root (descending).
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = 0.0;
      for (int k = 1; k <= n; ++k) {
        double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      double step = p0 / dp;
      z -= step;
      if (std::abs(step) < 1e-16) break;
    }
    x[i] = -z;
    x[n - 1 - i] = z;
    w[i] = w[n - 1 - i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

MuQuadrature gaussLegendreInSqrtMu(int n) {
  std::vector<double> x, w;
  gaussLegendre(n, x, w);
  MuQuadrature q;
  q.mu.resize(n);
  q.weight.resize(n);
  for (int i = 0; i < n; ++i) {
    double t = 0.5 * (x[i] + 1.0);
    q.mu[i] = t * t;
    q.weight[i] = w[i] * t;  // 0.5 w (for dt) times 2 t (for dmu = 2 t dt)
  }
  return q;
}

namespace {

// Solves A x = b in place (Gaussian elimination, partial pivoting); A is n x n, row major.
void solveLinear(std::vector<double>& a, std::vector<double>& b) {
  int n = static_cast<int>(b.size());
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[pivot * n + c])) pivot = r;
    if (pivot != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[pivot * n + k]);
      std::swap(b[c], b[pivot]);
    }
    for (int r = c + 1; r < n; ++r) {
      double f = a[r * n + c] / a[c * n + c];
      if (f == 0.0) continue;
      for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < n; ++k) s -= a[r * n + k] * b[k];
    b[r] = s / a[r * n + r];
  }
}

}  // namespace

HFunction::HFunction(double albedo, int nodes) : albedo_(albedo) {
  require(albedo > 0.0 && albedo <= 1.0, "H-function: albedo " + std::to_string(albedo) + " outside (0, 1]");
  require(nodes >= 4, "H-function: at least 4 nodes");
  MuQuadrature q = gaussLegendreInSqrtMu(nodes);
  mu_ = q.mu;
  weight_ = q.weight;
  root_ = std::sqrt(std::max(1.0 - albedo, 0.0));
  int n = nodes;
  // K_ij = (a/2) w_j mu_j / (mu_i + mu_j): 1/H_i = root + sum_j K_ij H_j.
  std::vector<double> kernel(n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) kernel[i * n + j] = 0.5 * albedo * weight_[j] * mu_[j] / (mu_[i] + mu_[j]);
  auto apply = [&](const std::vector<double>& h, std::vector<double>& s) {
    for (int i = 0; i < n; ++i) {
      double sum = root_;
      for (int j = 0; j < n; ++j) sum += kernel[i * n + j] * h[j];
      s[i] = sum;
    }
  };
  h_.assign(n, 1.0);
  std::vector<double> s(n);
  // Fixed point: a good start for Newton.
  for (int iteration = 0; iteration < 50; ++iteration) {
    apply(h_, s);
    for (int i = 0; i < n; ++i) h_[i] = 1.0 / s[i];
  }
  // Newton on F(h) = h (root + K h) - 1 = 0; J = diag(root + K h) + diag(h) K.
  for (int iteration = 0;; ++iteration) {
    apply(h_, s);
    std::vector<double> residual(n);
    double largest = 0.0;
    for (int i = 0; i < n; ++i) {
      residual[i] = h_[i] * s[i] - 1.0;
      largest = std::max(largest, std::abs(residual[i]));
    }
    if (largest < 1e-15) break;
    if (iteration == 50) fail(SS_INTERNAL_ERROR, "H-function: Newton did not converge for albedo " + std::to_string(albedo));
    std::vector<double> jacobian(n * n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) jacobian[i * n + j] = h_[i] * kernel[i * n + j] + (i == j ? s[i] : 0.0);
    solveLinear(jacobian, residual);
    for (int i = 0; i < n; ++i) h_[i] -= residual[i];
  }
}

double HFunction::operator()(double mu) const {
  double integral = 0.0;
  for (size_t j = 0; j < mu_.size(); ++j) integral += weight_[j] * mu_[j] * h_[j] / (mu + mu_[j]);
  return 1.0 / (root_ + 0.5 * albedo_ * integral);
}

double halfSpaceAlbedo(const HFunction& h, double mu0) {
  return 1.0 - std::sqrt(1.0 - h.albedo()) * h(mu0);
}

double halfSpaceReflectedRadiance(const HFunction& h, double mu0, double mu) {
  return h.albedo() * h(mu0) * h(mu) / (4.0 * M_PI * (mu0 + mu));
}

double halfSpaceUniformRadiance(const HFunction& h, double mu) {
  return 1.0 - std::sqrt(1.0 - h.albedo()) * h(mu);
}

double halfSpaceSingleScatteringAlbedo(double albedo, double mu0) {
  return 0.5 * albedo * (1.0 - mu0 * std::log1p(1.0 / mu0));
}

}  // namespace subsplat
