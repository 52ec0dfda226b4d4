#pragma once
// Importance sampling of the micrograin NDF, pdf D(m) cos theta_m per solid
// angle (LRPB23 Sec. 4.3, Eq. 19–20), isotropic and, through the unit space,
// anisotropic.
//
// Note on Eq. 20: as printed, theta = atan(beta sqrt(ln(1 - xi tau0) /
// (ln(1 - xi tau0) - ln(1 - tau0)))) has a negative radicand for xi in (0, 1)
// (numerator <= 0, denominator >= 0). The inverse of Eq. 19 is
// tan^2 theta = beta^2 ln(1 - xi tau0) / (ln(1 - tau0) - ln(1 - xi tau0)),
// which is what sample_ndf_theta implements.
//
// Ranges: tau0 in (0, 1); beta, beta_x, beta_y > 0; uniforms u, u1, u2 in [0, 1).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Inverse of Eq. 19 (Eq. 20, sign corrected): theta_m in [0, pi/2).
double sample_ndf_theta(double tau0, double beta, double u);

// Unit-space normal sampled from D1(m') cos theta' (u1 -> theta', u2 -> phi').
Vec3 sample_unit_ndf(double tau0, double u1, double u2);

// Real-space normal m with density D(m) cos theta_m per solid angle: sample the
// unit-space NDF and map it with from_unit_normal (exact for any beta_x, beta_y;
// for beta_x == beta_y this is Eq. 20 with phi_m = 2 pi u2).
Vec3 sample_ndf(const GrainField& f, double u1, double u2);

// The density of sample_ndf per unit solid angle: D(m) cos theta_m (0 below the horizon).
double ndf_pdf(const GrainField& f, Vec3 m);

}  // namespace mcref::micrograin
