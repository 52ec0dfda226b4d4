#pragma once
// Sampling of the micrograin visible NDF (vNDF paper Sec. 4, Listings 1–4),
// in the unit space, mapped to real normals for any beta_x, beta_y.
//
// theta (Listing 1, Eq. 23–25): Xi = -ln(1 - xi0 tau(i', 0)) / rho' is the
// projected area sigma(i', cos theta) to invert; without shadow
// (Xi <= pi cos^2 theta_i') cos theta = sqrt(1 - Xi/pi) (Eq. 25), otherwise a
// 1024 x 1024 table of sigma^-1 over (cos theta_i', normalised Xi), built at
// construction from the closed-form sigma (projected_area.h), read by
// bilinear interpolation.
//
// phi given theta (Sec. 4.2): the paper maps a tent approximation (Eq. 28–31)
// through the triangle-cut parameterisation (Heitz 2020, Listing 1 there, two
// uniforms). The triangle-cut listing is not in the texts we have, so here
// phi is the exact inverse of the conditional CDF (Eq. 22), by safeguarded
// Newton iterations started at the tent's inverse: one uniform, no bias.
// Note: Eq. 28 as printed has slope (h1 - h0)/phi_q, which grows with |phi|;
// the tent peaked at 0 with P~(±phi_q) = h0 and unit mass has slope
// (h0 - h1)/phi_q, used here.
//
// Ranges: tau0 in (0, 1); i real, unit, i.z > 0; uniforms in [0, 1).
#include <vector>

#include "models/micrograin/grain_field.h"
#include "sim/core/vec.h"

namespace mcref::micrograin {

class VndfSampler {
 public:
  static constexpr int kResolution = 1024;
  VndfSampler();  // builds the sigma^-1 table (~0.3 s)

  // cos theta' of a visible normal (Listing 1), i_unit the unit-space direction.
  double sample_cos_theta(double tau0, Vec3 i_unit, double xi) const;
  // phi' relative to the azimuth of i' (Sec. 4.2), given cos theta'.
  static double sample_phi(Vec3 i_unit, double cos_theta, double xi);
  // Unit-space visible normal (Listing 4).
  Vec3 sample_unit(double tau0, Vec3 i_unit, double u1, double u2) const;
  // Real-space visible normal, density visible_ndf(f, i, m) per solid angle.
  Vec3 sample(const GrainField& f, Vec3 i, double u1, double u2) const;

  // sigma^-1 from the table (for tests): h with sigma(i', h) = Xi, Xi in the shadow range.
  double inverse_sigma(double cos_theta_i, double xi_area) const;

 private:
  std::vector<float> table_;  // [row: cos theta_i][column: normalised Xi] -> h
};

// The tent approximation of the conditional pdf (Eq. 28 with the slope sign
// corrected) and its inverse CDF (Eq. 31): phi in [-phi_q, phi_q].
double tent_inverse(double phi_q, double h0, double xi);

}  // namespace mcref::micrograin
