#include "models/microfacet/fresnel.h"

#include <algorithm>
#include <cmath>

#include "models/core/quadrature.h"

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
  // Below the critical cosine mu_c (eta < 1) F = 1: 2 ∫ mu dmu = mu_c^2. Above it F
  // has a square-root kink at mu_c, removed by mu = mu_c + (1 - mu_c) s^2; the
  // rest is smooth: Gauss–Legendre, 16 panels of 16 points (~1e-15).
  const double mu_c = eta < 1 ? std::sqrt(1 - eta * eta) : 0;
  const double above = integrate_composite(
      [&](double s) {
        const double mu = mu_c + (1 - mu_c) * s * s;
        return fresnel_dielectric(mu, eta) * mu * 2 * (1 - mu_c) * s;
      },
      0, 1, 16, 16);
  return mu_c * mu_c + 2 * above;
}

}  // namespace mcref::micrograin
