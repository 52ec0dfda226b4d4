#pragma once
// Visible normal distribution of a micrograin field with the height-correlated
// masking G_dist (vNDF paper Sec. 3, Eq. 6, 11–13, 19, 21–22).
//
// D_v(i, m) is a density per unit solid angle of normals m, normalised over the
// grain hits seen from i: ∫ D_v(i, m) d omega_m = 1.
//
// Ranges: tau0 in (0, 1); beta_x, beta_y > 0; i a unit direction with i.z > 0
// (real or unit space as named); m a unit normal (D_v = 0 if m.z <= 0 or i.m <= 0).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Real space (Eq. 6 with tau(i, 0) = tau+(i), LRPB23 Eq. 22):
// D_v(i, m) = tau0 <i.m>+ D(m) G_dist(i, h(m)) / (tau+(i) cos theta_i),
// h(m) = unit_height(f, m). Equals det(M)/|M^T m|^3 D_v1(i', m') (Eq. 11–12).
double visible_ndf(const GrainField& f, Vec3 i, Vec3 m);

// Unit space (Eq. 13), i_unit and m_unit unit-space directions:
// D_v1(i', m') = rho' exp(-rho' sigma(i', h')) / (1 - exp(-rho' sigma(i', 0))) <i'.m'> / <i'.n>,
// h' = m'.z, rho' = -ln(1 - tau0)/pi.
double visible_ndf_unit(double tau0, Vec3 i_unit, Vec3 m_unit);

// Eq. 19: marginal CDF of the unit-space polar angle theta' of m under D_v,
// C(theta') = tau(i, cos theta') / tau(i, 0) (i real; theta' in [0, pi/2]).
double visible_ndf_marginal_cdf(const GrainField& f, Vec3 i, double theta_unit);

// Visibility bound phi_q of the ring of unit-space normals at polar angle
// theta_m for a unit-space direction at polar angle theta_i: <i'.m'> > 0 for
// |phi - phi_i| < phi_q; phi_q = acos(-1/(tan theta_i tan theta_m)), or pi
// when the whole ring is visible (tan theta_i tan theta_m <= 1).
double visible_azimuth_bound(double theta_i, double theta_m);

// Eq. 22 (with phi_q where the print has phi_i in the denominator): CDF of the
// azimuth phi of m' (relative to the azimuth of i') given theta_m, phi in
// [-phi_q, phi_q] (clamped outside):
// C = 1/2 + (sin phi sin theta_i sin theta_m + phi cos theta_i cos theta_m) /
//           (2 (sin phi_q sin theta_i sin theta_m + phi_q cos theta_i cos theta_m)).
double visible_ndf_conditional_cdf(double theta_i, double theta_m, double phi);

// Eq. 26 (same correction): the conditional density dC/dphi (0 outside [-phi_q, phi_q]).
double visible_ndf_conditional_pdf(double theta_i, double theta_m, double phi);

}  // namespace mcref::micrograin
