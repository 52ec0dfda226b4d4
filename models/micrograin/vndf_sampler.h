#pragma once
// Sampling of the micrograin visible NDF (vNDF paper Sec. 4, Listings 1–4),
// in the unit space, mapped to real normals for any beta_x, beta_y.
//
// theta (Listing 1, Eq. 23–25): Xi = -ln(1 - xi0 tau(i', 0)) / rho' is the
// projected area sigma(i', cos theta) to invert; without shadow
// (Xi <= pi cos^2 theta_i') cos theta = sqrt(1 - Xi/pi) (Eq. 25), otherwise a
// 1024 x 1024 table of sigma^-1 over (cos theta_i', normalised Xi), built at
// construction from the closed-form sigma (projected_area.h), stored as
// 16-bit fractions of sin theta_i', read by bilinear interpolation.
//
// phi given theta (Sec. 4.2, Listing 3): a tent approximation of the
// conditional pdf (Eq. 28–31) is sampled with one uniform and mapped through
// the triangle-cut parameterisation (Heitz 2020; models/core/triangle_cut.h)
// with a second one: exact, no rejection, no iteration.
// Notes on the printed formulas: the denominators of Eq. 22, 26 and 27 print
// phi_i where the tent's bound phi_q is meant and lack a factor sin theta_i';
// Eq. 28 as printed has slope (h1 - h0)/phi_q, which grows with |phi|; the
// tent peaked at 0 with P~(±phi_q) = h0 and unit mass has slope
// (h0 - h1)/phi_q, used here.
//
// Ranges: tau0 in (0, 1); i real, unit, i.z > 0; uniforms in [0, 1).
#include <cmath>
#include <cstdint>
#include <vector>

#include "models/core/small_angle.h"
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/phi_conditional.h"

namespace mcref::micrograin {

class VndfSampler {
 public:
  static constexpr int kResolution = 1024;
  VndfSampler();  // builds the sigma^-1 table (~0.3 s)

  // sin and cos of theta' of a visible normal (Listing 1; sin theta' from Xi
  // directly where Eq. 25 applies), for a unit-space i' at polar angle theta_i'.
  SinCos sample_theta(double tau0, double cos_theta_i, double sin_theta_i, double xi) const;
  // cos theta' alone.
  double sample_cos_theta(double tau0, double cos_theta_i, double sin_theta_i, double xi) const;
  // phi' relative to the azimuth of i' (Sec. 4.2, Listing 3), given cos theta'.
  static double sample_phi(Vec3 i_unit, double cos_theta, double u_s, double u_t);
  // Unit-space visible normal (Listing 4): u1 for theta', u2, u3 for phi'.
  Vec3 sample_unit(double tau0, Vec3 i_unit, double u1, double u2, double u3) const;
  // Real-space visible normal, density visible_ndf(f, i, m) per solid angle.
  Vec3 sample(const GrainField& f, Vec3 i, double u1, double u2, double u3) const;

  // sigma^-1 from the table (for tests): h with sigma(i', h) = Xi, Xi in the shadow range.
  double inverse_sigma(double cos_theta_i, double xi_area) const;
  double inverse_sigma(double cos_theta_i, double sin_theta_i, double xi_area) const;

 private:
  std::vector<std::uint16_t> table_;  // [row: cos theta_i][column: normalised Xi] -> h / sin theta_i, 16-bit
};

}  // namespace mcref::micrograin
