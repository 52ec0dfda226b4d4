#include "models/lambert_sphere/decay_rate.h"

#include <cmath>

#include "models/lambert_sphere/characteristic.h"

namespace mcref::lambert_sphere {

double dispersion_imaginary(double c, double s) {
  const PsiPolynomial psi = characteristic_polynomial(0, c);
  const double s2 = s * s;
  if (s <= 0.5) {  // 1 - 2 sum_n s^(2n) \int mu^(2n) Psi: terms shrink by 1/4 at least, 40 of them < 1e-24
    double sum = 0, power = 1;
    for (int n = 0; n < 40; ++n, power *= s2) sum += power * psi.even_moment(n);
    return 1 - 2 * sum;
  }
  // Psi = p0 + p2 u + p4 u^2 (u = mu^2) = (a0 + a1 u)(1 - s^2 u) + R, R = Psi at u = 1/s^2:
  // \int Psi / (1 - s^2 mu^2) = a0 + a1 / 3 + R atanh(s) / s.
  const auto& p = psi.coef;
  const double a1 = -p[2] / s2, a0 = (a1 - p[1]) / s2, r = p[0] + (p[1] + p[2] / s2) / s2;
  return 1 - 2 * (a0 + a1 / 3 + r * std::atanh(s) / s);
}

double decay_rate(double c) {
  // K(i s) falls from K(0) > 0 (c < 1) toward -inf as s -> 1 (Psi(1) > 0): bisect.
  double lo = 0, hi = 1 - 1e-15;
  if (!(c > 0) || dispersion_imaginary(c, hi) >= 0) return 1;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (dispersion_imaginary(c, mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace mcref::lambert_sphere
