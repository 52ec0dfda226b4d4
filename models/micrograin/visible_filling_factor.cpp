#include "models/micrograin/visible_filling_factor.h"

#include <cmath>

#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

// Every quantity here is 1 - (1 - tau0)^e for some exponent e; it is evaluated
// as -expm1(e ln(1 - tau0)) so that 1 - tau stays accurate near grazing angles
// (forming 1 - tau_beta from tau_beta would cancel catastrophically there).
namespace {
// e = gamma_beta / cos theta (isotropic) = 1 / cos theta' (unit space).
double full_exponent(double beta, double theta) {
  return compression_factor(beta, theta) / std::cos(theta);
}
double full_exponent(const GrainField& f, Vec3 d) { return 1.0 / to_unit_direction(f, d).z; }
double one_minus_pow(double tau0, double e) { return -std::expm1(std::log1p(-tau0) * e); }
}  // namespace

double compression_factor(double beta, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return std::sqrt(c * c + beta * beta * s * s);
}

double tau_beta(double tau0, double beta, double theta) {
  return one_minus_pow(tau0, full_exponent(beta, theta));  // Eq. 21
}

double tau_beta(const GrainField& f, Vec3 d) { return one_minus_pow(f.tau0, full_exponent(f, d)); }

// Eq. 22: 1 - sqrt((1 - tau_beta)(1 - tau0)) = 1 - (1 - tau0)^((e + 1)/2).
double tau_plus(double tau0, double beta, double theta) {
  return one_minus_pow(tau0, 0.5 * (full_exponent(beta, theta) + 1));
}

double tau_plus(const GrainField& f, Vec3 d) {
  return one_minus_pow(f.tau0, 0.5 * (full_exponent(f, d) + 1));
}

// Eq. 24: 1 - sqrt((1 - tau_beta(i))(1 - tau_beta(o))) = 1 - (1 - tau0)^((e_i + e_o)/2).
double layer_weight(const GrainField& f, Vec3 i, Vec3 o) {
  return one_minus_pow(f.tau0, 0.5 * (full_exponent(f, i) + full_exponent(f, o)));
}

double layer_weight_eq23(double tau0, double tau_plus_i, double tau_plus_o) {
  return 1 - (1 - tau_plus_i) * (1 - tau_plus_o) / (1 - tau0);  // Eq. 23
}

}  // namespace mcref::micrograin
