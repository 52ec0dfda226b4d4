#include "models/micrograin/grain_field.h"

#include <cmath>

#include "models/core/vec.h"

namespace mcref::micrograin {

GrainField isotropic_field(double tau0, double beta) { return GrainField{tau0, beta, beta}; }

double filling_factor(double rho, double r_x, double r_y) {
  return -std::expm1(-kPi * rho * r_x * r_y);  // Eq. 13
}

double density_from_filling_factor(double tau0, double r_x, double r_y) {
  return unit_density(tau0) / (r_x * r_y);
}

double unit_density(double tau0) { return -std::log1p(-tau0) / kPi; }

}  // namespace mcref::micrograin
