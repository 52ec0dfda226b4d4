#pragma once
// Height-dependent filling factor and the height-correlated ("distant")
// masking of LRPB24, as quoted in the vNDF paper (Eq. 3, 4, 9, 10).
//
// Directions are REAL unit directions (mapped internally to the unit space);
// h is the UNIT-SPACE height in [0, 1] (for a grain point of real normal m,
// h = unit_height(f, m) = m'.z). Ranges: f.tau0 in (0, 1), beta_x, beta_y > 0,
// i.z > 0.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// vNDF Eq. 4/10: tau(i, h) = 1 - exp(-rho' sigma(i', h)), rho' = -ln(1 - tau0)/pi.
// tau(n, 0) = tau0, and tau(i, 0) equals tau+ of LRPB23 Eq. 22.
double filling_factor_at_height(const GrainField& f, Vec3 i, double h);

// vNDF Eq. 3/9: G_dist(i, h) = exp(-rho' sigma(i', h)) / exp(-rho' sigma(n, h))
//                            = exp(-rho' sigma_s(i', h)).
double distant_masking(const GrainField& f, Vec3 i, double h);

}  // namespace mcref::micrograin
