#include "models/microfacet/fresnel.h"

#include <algorithm>
#include <cmath>

namespace mcref::micrograin {

namespace {

double fresnel_complex(double c, std::complex<double> eta) {
  c = std::clamp(c, 0.0, 1.0);
  const double sin2 = 1 - c * c;
  const std::complex<double> sin2_t = sin2 / (eta * eta);
  const std::complex<double> cos_t = std::sqrt(1.0 - sin2_t);
  const std::complex<double> r_p = (eta * c - cos_t) / (eta * c + cos_t);
  const std::complex<double> r_s = (c - eta * cos_t) / (c + eta * cos_t);
  return 0.5 * (std::norm(r_p) + std::norm(r_s));
}

}  // namespace

double fresnel_dielectric(double cos_theta, double eta) {
  const double c = std::clamp(cos_theta, 0.0, 1.0);
  const double sin2_t = (1 - c * c) / (eta * eta);
  if (sin2_t >= 1) return 1.0;  // total internal reflection
  const double cos_t = std::sqrt(1 - sin2_t);
  const double r_p = (eta * c - cos_t) / (eta * c + cos_t);
  const double r_s = (c - eta * cos_t) / (c + eta * cos_t);
  return 0.5 * (r_p * r_p + r_s * r_s);
}

double fresnel_conductor(double cos_theta, double eta, double kappa) {
  return fresnel_complex(cos_theta, {eta, kappa});
}

double fresnel_dielectric_average(double eta) {
  // Graded midpoint rule in mu (the TIR kink is resolved by many panels).
  const int n = 20000;
  double s = 0;
  for (int k = 0; k < n; ++k) {
    const double mu = (k + 0.5) / n;
    s += fresnel_dielectric(mu, eta) * mu;
  }
  return 2 * s / n;
}

}  // namespace mcref::micrograin
