#include "models/lambert_sphere/characteristic.h"

#include <cmath>
#include <stdexcept>

namespace mcref::lambert_sphere {

double PsiPolynomial::operator()(double mu) const {
  const double m2 = mu * mu;
  return coef[0] + m2 * (coef[1] + m2 * coef[2]);
}

double PsiPolynomial::even_moment(int n) const {
  return coef[0] / (2 * n + 1) + coef[1] / (2 * n + 3) + coef[2] / (2 * n + 5);
}

PsiPolynomial characteristic_polynomial(int m, double c) {
  switch (m) {
    case 0:  // Eq. 13: c (-15(c-1)(4c+9) mu^4 + (c(20c+281) - 346) mu^2 + 207) / 384
      return {{207 * c / 384, c * (c * (20 * c + 281) - 346) / 384, -15 * c * (c - 1) * (4 * c + 9) / 384}};
    case 1:  // Eq. 14: -c (mu^2 - 1)(5(4c+9) mu^2 - 64) / 192
      return {{-64 * c / 192, c * (5 * (4 * c + 9) + 64) / 192, -5 * c * (4 * c + 9) / 192}};
    case 2:  // Eq. 15: 15 c (mu^2 - 1)^2 / 256
      return {{15 * c / 256, -30 * c / 256, 15 * c / 256}};
    default:
      throw std::out_of_range("lambert_sphere::characteristic_polynomial: m not in {0, 1, 2}");
  }
}

double characteristic_psi(int m, double c, double mu) { return characteristic_polynomial(m, c)(mu); }

double dispersion_at_zero(int m, double c) {
  switch (m) {
    case 0: return (c - 16) * (c - 1) * (4 * c + 9) / 144;  // Eq. 32
    case 1: return 1 + c * (55 - 4 * c) / 144;
    case 2: return 1 - c / 16;
    default:
      throw std::out_of_range("lambert_sphere::dispersion_at_zero: m not in {0, 1, 2}");
  }
}

double dispersion_published(int m, double c, double t) {
  const double t2 = t * t, t3 = t2 * t, t5 = t3 * t2, at = std::atan(t);
  switch (m) {
    case 0:  // Eq. 18
      return 1 - c * ((256 * c - 301) * t3 +
                      ((346 - c * (20 * c + 281)) * t2 - 15 * (c - 1) * (4 * c + 9) + 207 * t2 * t2) * at +
                      15 * (c - 1) * (4 * c + 9) * t) /
                     (192 * t5);
    case 1:  // Eq. 19
      return 1 - c * ((40 * c + 282) * t3 - 3 * (t2 + 1) * (20 * c + 64 * t2 + 45) * at + 15 * (4 * c + 9) * t) /
                     (288 * t5);
    case 2:  // Eq. 20
      return 1 - 5 * c * (3 * (t2 + 1) * (t2 + 1) * at - t * (5 * t2 + 3)) / (128 * t5);
    default:
      throw std::out_of_range("lambert_sphere::dispersion_published: m not in {0, 1, 2}");
  }
}

double dispersion(int m, double c, double t) {
  t = std::fabs(t);
  if (std::isinf(t)) return 1.0;
  if (t >= 0.5) return dispersion_published(m, c, t);
  const PsiPolynomial psi = characteristic_polynomial(m, c);
  const double t2 = t * t;
  double s = 0, power = t2;
  for (int n = 1; n <= 40; ++n) {
    s += (n % 2 == 1 ? 1 : -1) * power * psi.even_moment(n);
    power *= t2;
  }
  return dispersion_at_zero(m, c) + 2 * s;
}

}  // namespace mcref::lambert_sphere
