#include "models/micrograin/ndf_sampling.h"

#include <cmath>

#include "models/micrograin/ndf.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {
// sin^2 theta' from the inverse of vNDF Eq. 14: ln(1 - u tau0) / ln(1 - tau0).
double unit_sin2(double tau0, double u) { return std::log1p(-u * tau0) / std::log1p(-tau0); }
}  // namespace

double sample_ndf_theta(double tau0, double beta, double u) {
  const double s2 = unit_sin2(tau0, u);
  // tan^2 theta_m = beta^2 tan^2 theta'; tan^2 theta' = s2 / (1 - s2)
  //   = ln(1 - u tau0) / (ln(1 - tau0) - ln(1 - u tau0))  (Eq. 20, sign corrected).
  return std::atan2(beta * std::sqrt(s2), std::sqrt(1 - s2));
}

Vec3 sample_unit_ndf(double tau0, double u1, double u2) {
  const double s2 = unit_sin2(tau0, u1);
  const double s = std::sqrt(s2), c = std::sqrt(1 - s2), phi = 2 * kPi * u2;
  return {s * std::cos(phi), s * std::sin(phi), c};
}

Vec3 sample_ndf(const GrainField& f, double u1, double u2) {
  return from_unit_normal(f, sample_unit_ndf(f.tau0, u1, u2));
}

double ndf_pdf(const GrainField& f, Vec3 m) { return m.z <= 0 ? 0.0 : ndf(f, m) * m.z; }

}  // namespace mcref::micrograin
