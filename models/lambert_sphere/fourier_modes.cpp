#include "models/lambert_sphere/fourier_modes.h"

#include <cmath>
#include <stdexcept>

#include "models/core/quadrature.h"
#include "models/core/vec.h"
#include "models/lambert_sphere/h_functions.h"
#include "models/lambert_sphere/phase_function.h"

namespace mcref::lambert_sphere {

double sine_product(double mu_i, double mu_o) {
  return std::sqrt(std::fmax(0.0, 1 - mu_i * mu_i) * std::fmax(0.0, 1 - mu_o * mu_o));
}

double first_mode(double c, double mu_i, double mu_o, double h1_i, double h1_o, const FirstModeConstants& k) {
  const double poly = 1 + (k.l * k.l + 45 * k.m / 64) * mu_i * mu_o + k.l * (mu_i + mu_o);
  return c * h1_i * h1_o * sine_product(mu_i, mu_o) * poly / (6 * kPi * (mu_i + mu_o));  // Eq. 22
}

double first_mode_fitted(double c, double mu_i, double mu_o) {
  return first_mode(c, mu_i, mu_o, h1_fit(c, mu_i), h1_fit(c, mu_o), first_mode_constants_fit(c));
}

double zeroth_mode(double mu_i, double mu_o, double h0_i, double h0_o, const ZerothModeConstants& k) {
  const double s = mu_i + mu_o, p = mu_i * mu_o;
  const double poly = k.A + k.B * s + k.C * p + k.D * p * s + k.E * p * p + k.F * (mu_i * mu_i + mu_o * mu_o);
  return h0_i * h0_o * poly / (2 * kPi * s);  // Eq. 30
}

double zeroth_mode_fitted(double c, double mu_i, double mu_o) {
  return zeroth_mode(mu_i, mu_o, h0_fit(c, mu_i), h0_fit(c, mu_o), zeroth_mode_constants_fit(c));
}

double single_scattering_zeroth_mode(double c, double mu_i, double mu_o) {
  const double a = mu_i * mu_i, b = mu_o * mu_o;
  return c * (45 * a * (3 * b - 1) + 256 * mu_i * mu_o - 45 * b + 207) / (768 * kPi * (mu_i + mu_o));  // Eq. 38
}

double single_scattering_first_mode_published(double c, double mu_i, double mu_o) {
  return c * (45 * mu_i * mu_o + 64) * sine_product(mu_i, mu_o) / (384 * kPi * (mu_i + mu_o));  // Eq. 28
}

double single_scattering_first_mode(double c, double mu_i, double mu_o) {
  return c * (45 * mu_i * mu_o + 64) * sine_product(mu_i, mu_o) / (192 * kPi * (mu_i + mu_o));
}

double single_scattering_second_mode(double c, double mu_i, double mu_o) {
  const double s = sine_product(mu_i, mu_o);
  return 15 * c * s * s / (256 * kPi * (mu_i + mu_o));
}

double single_scattering_mode_numeric(double c, double mu_i, double mu_o, int m, PhaseModel phase) {
  if (m < 0) throw std::invalid_argument("single_scattering_mode_numeric: m < 0");
  static thread_local const GaussLegendre rule(20);
  const double s = sine_product(mu_i, mu_o);
  auto integrand = [&](double phi) {
    const double x = -mu_i * mu_o - s * std::cos(phi);  // cosine of -omega_i . omega_o
    const double p = phase == PhaseModel::exact ? phase_function(x) : phase_function_three_term(x);
    return c * p / (mu_i + mu_o) * std::cos(m * phi);
  };
  // f_m = (1 + [m > 0]) / pi \int_0^pi f(phi) cos(m phi) dphi; panels [pi 2^-(j+1), pi 2^-j].
  double sum = rule.integrate(integrand, 0.0, kPi * std::ldexp(1.0, -40));
  for (int j = 39; j >= 0; --j) sum += rule.integrate(integrand, kPi * std::ldexp(1.0, -(j + 1)), kPi * std::ldexp(1.0, -j));
  return (m == 0 ? 1.0 : 2.0) * sum / kPi;
}

double multiple_zeroth_mode_fitted(double c, double mu_i, double mu_o) {
  return zeroth_mode_fitted(c, mu_i, mu_o) - single_scattering_zeroth_mode(c, mu_i, mu_o);  // Eq. 38
}

double multiple_first_mode_from(double first_mode_eq22, double c, double mu_i, double mu_o,
                                FirstModeVariant variant) {
  switch (variant) {
    case FirstModeVariant::published:
      return first_mode_eq22 - single_scattering_first_mode_published(c, mu_i, mu_o);
    case FirstModeVariant::subtract_192:
      return first_mode_eq22 - single_scattering_first_mode(c, mu_i, mu_o);
    case FirstModeVariant::corrected:
      return 2 * first_mode_eq22 - single_scattering_first_mode(c, mu_i, mu_o);
    case FirstModeVariant::fast:
      return multiple_first_mode_fast(c, mu_i, mu_o);
  }
  throw std::invalid_argument("multiple_first_mode_from: unknown variant");
}

double multiple_first_mode_fitted(double c, double mu_i, double mu_o, FirstModeVariant variant) {
  if (variant == FirstModeVariant::fast) return multiple_first_mode_fast(c, mu_i, mu_o);
  return multiple_first_mode_from(first_mode_fitted(c, mu_i, mu_o), c, mu_i, mu_o, variant);
}

double multiple_first_mode_fast(double c, double mu_i, double mu_o) {
  return -0.0117 * c * std::atan(c) * sine_product(mu_i, mu_o) * std::sqrt(std::tanh(mu_i + mu_i * mu_o + mu_o)) /
         (mu_i + mu_o);  // Eq. 29
}

}  // namespace mcref::lambert_sphere
