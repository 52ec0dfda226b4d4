#pragma once
// Gauss-Legendre quadrature on [a, b]; nodes by Newton iteration on P_n.
#include <cmath>
#include <optional>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

struct GaussLegendre {
  std::vector<double> x, w;  // nodes and weights on [-1, 1]
  explicit GaussLegendre(int n);
  // Integral of f over [a, b].
  template <class F>
  double integrate(F&& f, double a, double b) const {
    const double h = 0.5 * (b - a), c = 0.5 * (b + a);
    double s = 0;
    for (std::size_t i = 0; i < x.size(); ++i) s += w[i] * f(c + h * x[i]);
    return s * h;
  }
};

inline GaussLegendre::GaussLegendre(int n) : x(n), w(n) {
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = 0;
      for (int k = 1; k <= n; ++k) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2 * k - 1) * z * p1 - (k - 1) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1);
      const double dz = p0 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-15) break;
    }
    x[i] = -z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

// Composite Gauss-Legendre: `panels` panels of an n-point rule, for integrands
// with kinks or steep parts (e.g. near grazing angles).
template <class F>
double integrate_composite(F&& f, double a, double b, int panels = 16, int n = 16) {
  static const GaussLegendre rule16(16);
  std::optional<GaussLegendre> other;
  if (n != 16) other.emplace(n);
  const GaussLegendre& rule = other ? *other : rule16;
  const double h = (b - a) / panels;
  double s = 0;
  for (int p = 0; p < panels; ++p) s += rule.integrate(f, a + p * h, a + (p + 1) * h);
  return s;
}

// Adaptive Gauss-Legendre: a 10-point rule on [a, b] is accepted when it agrees
// with the sum over the two halves to within tol (absolute); otherwise each half
// is refined with tol / 2, at most max_depth levels, and a piece is also
// accepted once the two agree to rounding (1e-14 relative). For integrands smooth on
// [a, b] (split kinks first) the result is then accurate to about tol.
template <class F>
double integrate_adaptive(const F& f, double a, double b, double tol, int max_depth = 30) {
  static const GaussLegendre g(10);
  struct Step {
    static double run(const F& f, double a, double b, double whole, double tol, int depth) {
      const double m = 0.5 * (a + b);
      const double left = g.integrate(f, a, m), right = g.integrate(f, m, b);
      const double diff = std::fabs(left + right - whole);
      // Also stop at the rounding floor, where halving tol could never be met.
      if (depth <= 0 || diff <= tol || diff <= 1e-14 * (std::fabs(left) + std::fabs(right))) return left + right;
      return run(f, a, m, left, 0.5 * tol, depth - 1) + run(f, m, b, right, 0.5 * tol, depth - 1);
    }
  };
  return Step::run(f, a, b, g.integrate(f, a, b), tol, max_depth);
}

}  // namespace mcref
