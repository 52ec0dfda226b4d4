#pragma once
// Gauss-Legendre quadrature on [a, b]; nodes by Newton iteration on P_n.
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

}  // namespace mcref
