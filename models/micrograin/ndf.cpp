#include "models/micrograin/ndf.h"

#include <cmath>

#include "models/micrograin/ggx.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {
// -ln(1 - tau0) / tau0, with its limit 1 at tau0 = 0.
double log_ratio(double tau0) { return tau0 == 0 ? 1.0 : -std::log1p(-tau0) / tau0; }
}  // namespace

double unit_ndf(double tau0, double cos_theta_unit) {
  const double s2 = 1 - cos_theta_unit * cos_theta_unit;
  return log_ratio(tau0) / kPi * std::exp(std::log1p(-tau0) * s2);  // vNDF Eq. 8
}

double ndf_eq16(double tau0, double beta, double theta_m) {
  const double a = -std::log1p(-tau0);  // pi rho r_s^2
  const double c = std::cos(theta_m), t = std::tan(theta_m), b2 = beta * beta;
  const double q = b2 + t * t;
  return b2 * (a / kPi) * std::exp(-a * t * t / q) / (-std::expm1(-a) * q * q * c * c * c * c);
}

double ndf(double tau0, double beta, double theta_m) {
  const double c = std::cos(theta_m), s = std::sin(theta_m);
  const double e = s * s / (beta * beta * c * c + s * s);  // tan^2 / (beta^2 + tan^2)
  return log_ratio(tau0) * std::exp(std::log1p(-tau0) * e) * ggx_ndf(beta, theta_m);  // Eq. 17
}

double ndf(const GrainField& f, Vec3 m) {
  if (m.z <= 0) return 0.0;
  const double s = normal_stretch(f, m);
  const double h = m.z / s;  // cos theta' of the unit-space normal
  return unit_ndf(f.tau0, h) / (f.beta_x * f.beta_y * s * s * s * s);  // vNDF Eq. 7
}

double equivalent_roughness(double tau0, double beta) {
  return beta / std::sqrt(log_ratio(tau0));  // Eq. 18
}

double ndf_cdf_theta(double tau0, double beta, double theta_m) {
  const double c = std::cos(theta_m), s = std::sin(theta_m);
  const double e = s * s / (beta * beta * c * c + s * s);
  return tau0 == 0 ? e : -std::expm1(std::log1p(-tau0) * e) / tau0;  // Eq. 19
}

double ndf_cdf_unit_theta(double tau0, double theta_unit) {
  const double s = std::sin(theta_unit);
  return tau0 == 0 ? s * s : -std::expm1(std::log1p(-tau0) * s * s) / tau0;  // vNDF Eq. 14
}

}  // namespace mcref::micrograin
