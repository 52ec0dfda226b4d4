#include "models/micrograin/height_masking.h"

#include <cmath>

#include "models/micrograin/projected_area.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

double filling_factor_at_height(const GrainField& f, Vec3 i, double h) {
  // exp(-rho' sigma) = (1 - tau0)^(sigma / pi)
  return -std::expm1(std::log1p(-f.tau0) * projected_cap_area(to_unit_direction(f, i), h) / kPi);
}

double distant_masking(const GrainField& f, Vec3 i, double h) {
  return std::exp(std::log1p(-f.tau0) * cap_shadow_area(to_unit_direction(f, i), h) / kPi);
}

}  // namespace mcref::micrograin
