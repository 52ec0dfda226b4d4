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
  // F_k = (pi gamma)^{k+1} / (2 (k+1)!) (S_k(x) / (1 + x)^{k - 1/2} - 1), x = beta^2 / mu^2,
  // S_k the binomial series of (1 + x)^{k - 1/2} cut after x^k (the closed forms of
  // papers/README.md for k <= 4, written for any k). The bracket is minus the series'
  // tail over (1 + x)^{k - 1/2}; for x < 1/2 the tail is summed directly (no cancellation).
  const double pg = -std::log1p(-tau0);
  const double mu = std::cos(theta) / std::sin(theta);
  const double x = beta * beta / (mu * mu), a = k - 0.5;
  const double scale = 0.5 * std::exp((k + 1) * std::log(pg) - std::lgamma(k + 2.0));
  double c = 1, xj = 1, head = 1;  // C(a, j), x^j, S_j
  for (int j = 1; j <= k; ++j) {
    c *= (a - j + 1) / j;
    xj *= x;
    head += c * xj;
  }
  const double power = std::pow(1 + x, a);
  if (x >= 0.5) return scale * (head / power - 1);
  double tail = 0;
  for (int j = k + 1; j < 10000; ++j) {
    c *= (a - j + 1) / j;
    xj *= x;
    const double t = c * xj;
    tail += t;
    if (std::fabs(t) <= 1e-17 * std::fabs(tail)) break;
  }
  return -scale * tail / power;
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
