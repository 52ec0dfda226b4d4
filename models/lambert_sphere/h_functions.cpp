#include "models/lambert_sphere/h_functions.h"

#include <cmath>
#include <limits>

#include "models/lambert_sphere/characteristic.h"

namespace mcref::lambert_sphere {

double h_exact(int m, double c, double mu) {
  return radiative_transfer::h_function_from_dispersion([m, c](double t) { return dispersion(m, c, t); }, mu);
}

radiative_transfer::HTable h_table(int m, double c) {
  const PsiPolynomial psi = characteristic_polynomial(m, c);
  return radiative_transfer::HTable(psi, [m, c](double t) { return dispersion(m, c, t); });
}

double h1_fit_conservative(double mu) {
  const double e = ((-1.12831 * mu + 1.85728) * mu - 1.07879) * mu + 0.459442;
  return std::exp(-0.0894878 * std::pow(mu, e));
}

double h1_fit_at_one(double c) { return std::exp(0.0242851 * c * c - 0.144839 * c); }

double h1_fit(double c, double mu) { return h1_fit_at_one(c) * h1_fit_conservative(mu); }

double h1_fit_log_separable(double c, double mu) {
  if (mu <= 0) return 1.0;
  const double e = ((-1.12831 * mu + 1.85728) * mu - 1.07879) * mu + 0.459442;
  return std::exp(std::log(h1_fit_at_one(c)) * std::pow(mu, e));
}

double h0_at_infinity(double c) {
  const double k0 = (c - 16) * (c - 1) * (4 * c + 9);
  return k0 > 0 ? 12 / std::sqrt(k0) : std::numeric_limits<double>::infinity();
}

double h0_fit(double c, double mu) {
  const double s = std::sqrt(1 - c);
  const double a = (1.50112 * std::pow(s, 6.05435) + 8.21644) / (4.17593 - 1.21222 * s);
  const double d = (7.7731 - 0.565811 * std::pow(s, 0.961546)) / (8.65912 - 0.159974 * std::pow(s, 7));
  const double amd = a * std::pow(mu, d);
  return (1 + amd) / (1 + amd / h0_at_infinity(c));
}

}  // namespace mcref::lambert_sphere
