#include "models/lambert_sphere/phase_function.h"

#include <cmath>
#include <stdexcept>

#include "models/core/quadrature.h"
#include "models/core/vec.h"

namespace mcref::lambert_sphere {

double phase_function(double mu) {
  mu = std::fmin(1.0, std::fmax(-1.0, mu));
  return 2 * (std::sqrt(1 - mu * mu) - mu * std::acos(mu)) / (3 * kPi * kPi);
}

double legendre_polynomial(int k, double x) {
  if (k == 0) return 1.0;
  double p0 = 1, p1 = x;
  for (int n = 2; n <= k; ++n) {
    const double p2 = ((2 * n - 1) * x * p1 - (n - 1) * p0) / n;
    p0 = p1;
    p1 = p2;
  }
  return p1;
}

double legendre_coefficient(int k) {
  if (k < 0) throw std::out_of_range("lambert_sphere::legendre_coefficient: k < 0");
  static thread_local const GaussLegendre rule(64);
  // mu = cos(t): dmu = sin(t) dt, acos(mu) = t.
  const double integral = rule.integrate(
      [k](double t) {
        const double p = 2 * (std::sin(t) - t * std::cos(t)) / (3 * kPi * kPi);
        return p * legendre_polynomial(k, std::cos(t)) * std::sin(t);
      },
      0.0, kPi);
  return 2 * kPi * (2 * k + 1) * integral;
}

double published_legendre_coefficient(int k) {
  static constexpr double kA[7] = {1.0, -4.0 / 3.0, 5.0 / 16.0, 0.0, 1.0 / 64.0, 0.0, 13.0 / 4096.0};
  if (k < 0 || k > 6) throw std::out_of_range("lambert_sphere::published_legendre_coefficient: k not in [0, 6]");
  return kA[k];
}

double phase_function_three_term(double mu) {
  return (1 - 4 * mu / 3 + 5.0 / 16.0 * 0.5 * (3 * mu * mu - 1)) / (4 * kPi);
}

}  // namespace mcref::lambert_sphere
