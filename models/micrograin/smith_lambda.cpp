#include "models/micrograin/smith_lambda.h"

#include <algorithm>
#include <cmath>

#include "models/core/quadrature.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {

constexpr int kPanels = 24;  // panels of 16 Gauss-Legendre points

// (1/cos theta) ∫ <w.m>^- W(theta_m) dm for an azimuthally symmetric weight W,
// w at polar angle theta. W is called with (theta_m, cos^2 theta') where
// theta' is the unit-space angle of the normal for slope scale beta.
template <class Weight>
double negative_part_integral(double beta, double theta, Weight&& weight) {
  if (theta <= 0) return 0.0;
  const double sin_w = std::sin(theta), cos_w = std::cos(theta);
  // <w.m> < 0 somewhere on the ring of theta_m iff theta_m > pi/2 - theta, i.e.
  // theta' > t0 with tan t0 = cot theta / beta.
  const double t0 = std::atan2(cos_w, beta * sin_w);
  const double span = 0.5 * kPi - t0;
  auto integrand = [&](double v) {
    const double tp = t0 + span * v * v;  // quadratic grading at the kink
    const double sp = std::sin(tp), cp = std::cos(tp);
    const double theta_m = std::atan2(beta * sp, cp);
    const double sm = std::sin(theta_m), cm = std::cos(theta_m);
    const double dtheta_m = beta / (cp * cp + beta * beta * sp * sp);  // d theta_m / d theta'
    const double a = sin_w * sm, b = cos_w * cm;
    const double cos_phi0 = std::clamp(-b / a, -1.0, 1.0);
    const double phi0 = std::acos(cos_phi0);
    const double ring = 2 * (a * std::sqrt(1 - cos_phi0 * cos_phi0) - b * (kPi - phi0));
    return weight(theta_m, cp * cp) * sm * ring * dtheta_m * 2 * span * v;
  };
  return integrate_composite(integrand, 0.0, 1.0, kPanels, 16) / cos_w;
}

}  // namespace

double lambda_series_term(double tau0, double beta, double theta, int k) {
  const double pg = -std::log1p(-tau0);
  const double mu = std::cos(theta) / std::sin(theta);
  const double b2 = beta * beta, b4 = b2 * b2, b6 = b4 * b2, b8 = b4 * b4;
  const double m2 = mu * mu, m4 = m2 * m2, m6 = m4 * m2, m8 = m4 * m4;
  const double R = std::sqrt(b2 + mu * mu), R3 = R * R * R, R5 = R3 * R * R, R7 = R5 * R * R;
  switch (k) {
    case 0: return pg * (R - mu) / (2 * mu);
    case 1: return std::pow(pg, 2) * (b2 + 2 * mu * (mu - R)) / (8 * mu * R);
    case 2: return std::pow(pg, 3) * (3 * b4 + 12 * b2 * m2 + 8 * m4 - 8 * mu * R3) / (96 * mu * R3);
    case 3:
      return std::pow(pg, 4) * (5 * b6 + 30 * b4 * m2 + 40 * b2 * m4 + 16 * m6 - 16 * mu * R5) /
             (768 * mu * R5);
    case 4:
      return std::pow(pg, 5) *
             (35 * b8 + 280 * b6 * m2 + 560 * b4 * m4 + 448 * b2 * m6 + 128 * m8 - 128 * mu * R7) /
             (30720 * mu * R7);
    default: return lambda_series_term_quadrature(tau0, beta, theta, k);
  }
}

double lambda_series_term_quadrature(double tau0, double beta, double theta, int k) {
  const double pg = -std::log1p(-tau0);
  const double ik = negative_part_integral(beta, theta, [&](double theta_m, double c2) {
    return std::pow(c2, k) * ggx_ndf(beta, theta_m);  // (1 - s)^k D_GGX
  });
  return std::exp((k + 1) * std::log(pg) - std::lgamma(k + 1.0)) * ik;  // (pi gamma)^{k+1}/k!
}

double lambda_series(const GrainField& f, double theta, int n) {
  if (theta <= 0) return 0.0;
  double sum = 0;
  for (int k = 0; k <= n; ++k) sum += lambda_series_term(f.tau0, f.beta_x, theta, k);
  return sum * (1 - f.tau0) / f.tau0;  // 1 / (e^{pi gamma} - 1) = (1 - tau0) / tau0
}

double lambda_quadrature(const GrainField& f, double theta) {
  const double beta = f.beta_x;
  return negative_part_integral(beta, theta,
                                [&](double theta_m, double) { return ndf(f.tau0, beta, theta_m); });
}

double lambda_quadrature(const GrainField& f, Vec3 d) {
  const double theta_unit = spherical_theta(to_unit_direction(f, d));
  return lambda_quadrature(GrainField{f.tau0, 1.0, 1.0}, theta_unit);
}

double lambda_ggx_equivalent(const GrainField& f, double theta) {
  return ggx_lambda(equivalent_roughness(f.tau0, f.beta_x), theta);
}

}  // namespace mcref::micrograin
