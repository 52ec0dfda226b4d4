#include "models/micrograin/visible_ndf.h"

#include <algorithm>
#include <cmath>

#include "models/micrograin/height_masking.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/projected_area.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"

namespace mcref::micrograin {

double visible_ndf(const GrainField& f, Vec3 i, Vec3 m) {
  const double im = dot(i, m);
  if (m.z <= 0 || im <= 0) return 0.0;
  const double g = distant_masking(f, i, unit_height(f, m));
  return f.tau0 * im * ndf(f, m) * g / (tau_plus(f, i) * i.z);  // Eq. 6
}

double visible_ndf_unit(double tau0, Vec3 i_unit, Vec3 m_unit) {
  const double im = dot(i_unit, m_unit);
  if (m_unit.z <= 0 || im <= 0) return 0.0;
  const double lg = std::log1p(-tau0);  // -rho' pi
  const double num = -lg / kPi * std::exp(lg * projected_cap_area(i_unit, m_unit.z) / kPi);
  const double den = -std::expm1(lg * projected_cap_area(i_unit, 0.0) / kPi);
  return num / den * im / i_unit.z;  // Eq. 13
}

double visible_ndf_marginal_cdf(const GrainField& f, Vec3 i, double theta_unit) {
  return filling_factor_at_height(f, i, std::cos(theta_unit)) /
         filling_factor_at_height(f, i, 0.0);  // Eq. 19
}

double visible_azimuth_bound(double theta_i, double theta_m) {
  const double p = std::tan(theta_i) * std::tan(theta_m);
  return p <= 1 ? kPi : std::acos(-1 / p);
}

namespace {
// Normalisation of Eq. 21: ∫_{-phi_q}^{phi_q} <i'.m'> dphi / 2.
double ring_half_integral(double st, double ct, double phi_q) {
  return std::sin(phi_q) * st + phi_q * ct;
}
}  // namespace

double visible_ndf_conditional_cdf(double theta_i, double theta_m, double phi) {
  const double phi_q = visible_azimuth_bound(theta_i, theta_m);
  phi = std::clamp(phi, -phi_q, phi_q);
  const double st = std::sin(theta_i) * std::sin(theta_m), ct = std::cos(theta_i) * std::cos(theta_m);
  return 0.5 + 0.5 * (std::sin(phi) * st + phi * ct) / ring_half_integral(st, ct, phi_q);  // Eq. 22
}

double visible_ndf_conditional_pdf(double theta_i, double theta_m, double phi) {
  const double phi_q = visible_azimuth_bound(theta_i, theta_m);
  if (std::fabs(phi) > phi_q) return 0.0;
  const double st = std::sin(theta_i) * std::sin(theta_m), ct = std::cos(theta_i) * std::cos(theta_m);
  return 0.5 * (std::cos(phi) * st + ct) / ring_half_integral(st, ct, phi_q);  // Eq. 26
}

}  // namespace mcref::micrograin
