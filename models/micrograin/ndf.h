#pragma once
// Micrograin normal distribution function (LRPB23 Sec. 4.2; vNDF paper Eq. 2,
// 7, 8). Real-space D(m), normalised over the grain-covered part of the plane:
// ∫ D(m) cos theta_m d omega_m = 1 over the upper hemisphere.
//
// Ranges: tau0 in (0, 1) (tau0 -> 0 gives GGX; tau0 == 0 returns that limit);
// beta, beta_x, beta_y > 0; theta in [0, pi/2]; m a unit vector (D = 0 for m.z <= 0).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Unit-space NDF (vNDF Eq. 8): D1(m') = rho' exp(-rho' pi sin^2 theta') / tau0,
// rho' = -ln(1 - tau0)/pi; a function of cos theta' = m'.z = h only.
double unit_ndf(double tau0, double cos_theta_unit);

// LRPB23 Eq. 16, with pi rho r_s^2 = -ln(1 - tau0) (isotropic; theta_m < pi/2).
double ndf_eq16(double tau0, double beta, double theta_m);

// LRPB23 Eq. 17: D = -ln(1 - tau0) (1 - tau0)^(tan^2/(beta^2 + tan^2)) / tau0 * D_GGX(m; beta).
double ndf(double tau0, double beta, double theta_m);

// Anisotropic real-space NDF via the unit-space transform (vNDF Eq. 7):
// D(m) = det(M) / |M^T m|^4 * D1(m'), det(M) = 1/(beta_x beta_y). Reduces to
// Eq. 17 when beta_x == beta_y and to anisotropic GGX(beta_x, beta_y) as tau0 -> 0.
double ndf(const GrainField& f, Vec3 m);

// LRPB23 Eq. 18: equivalent GGX roughness alpha~ = beta sqrt(-tau0 / ln(1 - tau0)).
double equivalent_roughness(double tau0, double beta);

// LRPB23 Eq. 19: CDF of theta_m under D(m) cos theta_m (isotropic):
// C(theta) = (1 - (1-tau0)^(tan^2/(beta^2+tan^2))) / tau0.
double ndf_cdf_theta(double tau0, double beta, double theta_m);

// Same CDF in terms of the unit-space angle (beta = 1), valid for anisotropic
// fields: C(theta') = (1 - (1-tau0)^(sin^2 theta')) / tau0 (vNDF Eq. 14).
double ndf_cdf_unit_theta(double tau0, double theta_unit);

}  // namespace mcref::micrograin
