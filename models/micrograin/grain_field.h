#pragma once
// Parameters of a micrograin field (LRPB23 Sec. 3–4; vNDF paper Sec. 2).
//
// Grain centres form a Poisson process of density rho on the plane z = 0; each
// grain is the upper half of an ellipsoid with horizontal semi-axes r_x, r_y and
// vertical semi-axis c. Everything the analytic models need is scale-invariant,
// so a field is described by the filling factor tau0 and the slope scales
// beta_x = c / r_x, beta_y = c / r_y (isotropic: beta_x == beta_y == beta).
//
// "Unit space" (unit_space.h) scales x by 1/r_x, y by 1/r_y, z by 1/c, so the
// grains become unit hemispheres with the unit-space density
// rho' = rho r_x r_y = -ln(1 - tau0) / pi.
//
// Valid ranges (validated by the config layer, assumed here):
//   tau0 in (0, 1); beta_x, beta_y > 0 (LRPB23 uses beta in (0, 1], the vNDF
//   paper also beta > 1); rho >= 0, r_x, r_y > 0.

namespace mcref::micrograin {

struct GrainField {
  double tau0;    // filling factor tau0 = 1 - exp(-pi rho r_x r_y), in (0, 1)
  double beta_x;  // c / r_x > 0
  double beta_y;  // c / r_y > 0
};

// An isotropic field (beta_x == beta_y == beta).
GrainField isotropic_field(double tau0, double beta);

// LRPB23 Eq. 13: tau0 = 1 - exp(-pi rho r_x r_y) (isotropic: r_x = r_y = r_s).
double filling_factor(double rho, double r_x, double r_y);

// Inverse of Eq. 13: rho = -ln(1 - tau0) / (pi r_x r_y).
double density_from_filling_factor(double tau0, double r_x, double r_y);

// Unit-space density rho' = rho r_x r_y = -ln(1 - tau0) / pi.
double unit_density(double tau0);

}  // namespace mcref::micrograin
