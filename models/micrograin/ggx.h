#pragma once
// Trowbridge–Reitz (GGX) NDF and its Smith Lambda, the tau0 -> 0 limit of the
// micrograin NDF (LRPB23 Eq. 17) and the "GGX G1 at the equivalent roughness"
// alternative of LRPB23 Sec. 5.2.
//
// Ranges: alpha, alpha_x, alpha_y > 0; theta in [0, pi/2]; m a unit vector.
#include "models/core/vec.h"

namespace mcref::micrograin {

// D_GGX(m) = alpha^2 / (pi (alpha^2 cos^2 theta_m + sin^2 theta_m)^2),
// normalised: ∫ D cos theta_m d omega = 1 over the upper hemisphere.
double ggx_ndf(double alpha, double theta_m);

// Anisotropic GGX: 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi/ax^2 + sin^2 phi/ay^2))^2);
// zero for m.z <= 0.
double ggx_ndf(double alpha_x, double alpha_y, Vec3 m);

// Smith Lambda of GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2 (infinite at pi/2).
double ggx_lambda(double alpha, double theta);

// G1 = 1 / (1 + Lambda).
double smith_g1(double lambda);

}  // namespace mcref::micrograin
