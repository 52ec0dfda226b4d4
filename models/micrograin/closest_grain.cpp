#include "models/micrograin/closest_grain.h"

#include <cmath>

#include "models/core/vec.h"

namespace mcref::micrograin {

double closest_grain_distance_pdf(double r, double rho) {
  return 2 * kPi * rho * r * std::exp(-kPi * rho * r * r);  // Eq. 8
}

double closest_grain_distance_cdf(double r, double rho) {
  return -std::expm1(-kPi * rho * r * r);  // Eq. 9
}

double closest_grain_polar_pdf(double r, double rho) {
  return rho * std::exp(-kPi * rho * r * r);  // Eq. 10
}

double closest_grain_distance_pdf_finite(double r, double rho, double n) {
  const double x = kPi * rho * r * r / n;  // P_n(r) = r^2 / R^2 (Eq. 4)
  if (x >= 1) return 0.0;
  return 2 * kPi * rho * r * std::pow(1 - x, n - 1);  // Eq. 7
}

}  // namespace mcref::micrograin
