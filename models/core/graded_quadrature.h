#pragma once
// Adaptive Gauss-Legendre for a piece whose ends are kinks of the integrand
// (e.g. |x - a|^(3/2) or sqrt-like edges, where a model's visibility starts):
// the map x = a + (b - a) s(t), s = 3t^2 - 2t^3, has the Jacobian
// 6 t (1 - t) (b - a), which vanishes at both ends, so such an end behaviour
// becomes a smooth power of t and the adaptive rule no longer crowds the ends.
#include "models/core/quadrature.h"

namespace mcref {

template <class F>
double integrate_adaptive_graded(const F& f, double a, double b, double tol) {
  const double w = b - a;
  auto mapped = [&](double t) { return f(a + w * t * t * (3 - 2 * t)) * 6 * t * (1 - t) * w; };
  return integrate_adaptive(mapped, 0.0, 1.0, tol);
}

}  // namespace mcref
