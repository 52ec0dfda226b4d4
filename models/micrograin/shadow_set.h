#pragma once
// The shadow set K_d(h) of one direction (vNDF paper Eq. 3/9; issue #15): the
// centres c (z = 0) of the unit grains that hide the point p = (0, 0, h) from d,
// i.e. come within distance 1 of the half-line p + t d, t >= 0. In d's frame
// (x along d's azimuth phi_d, theta = theta_d), the slice z = 0 of that capsule is
//   K_d(h) = disc |c| < rs = sqrt(1 - h^2)  U  (E ∩ {x >= h cot theta}),
//   E: ((x + h tan theta) cos theta)^2 + y^2 < 1       (the cylinder around the line),
// E ⊇ disc, tangent to it on the line x = h cot theta, where
//   f_E - f_disc = -(x sin theta - h cos theta)^2 <= 0.
// E's boundary is x = -h tan theta + cos t / cos theta, y = sin t; the arc beyond
// the disc is |t| <= t_k, cos t_k = h / sin theta (none if h >= sin theta). The
// origin lies inside E and K_d(h) is convex, so both are star-shaped about it, and
// the area swept by E's boundary from t1 to t2 is
//   1/2 ∫ (x y' - y x') dt = 1/2 [(t2 - t1) / cos theta - h tan theta (sin t2 - sin t1)].
//
// Directions: unit-space, z > 0; h in [0, 1].
#include "models/core/vec.h"

namespace mcref::micrograin {

struct ShadowSet {
  double s, c, phi;  // sin, cos and azimuth of the unit-space direction
  double h, rs;      // height and the disc's radius sqrt(1 - h^2)
  double tk;         // E's arc beyond the disc: |t| <= tk; -1 if there is none
  double psik;       // its azimuths relative to phi: |psi - phi| <= psik

  ShadowSet(Vec3 d_unit, double h);
  bool has_arc() const { return tk >= 0; }
  // Radius of K_d(h) at azimuth psi: E's where psi is within the arc, else rs.
  double radius(double psi) const;
  // Radius of E at azimuth x relative to phi (|x| <= pi/2 within the arc).
  double ellipse_radius(double x) const;
  // E's parameter t of its boundary point at azimuth psi (within the arc).
  double param(double psi) const;
  // Area of E's sector from t1 to t2 minus the disc's sector over the same
  // azimuth range dpsi: the excess of K_d(h) over the disc there.
  double arc_excess(double t1, double t2, double dpsi) const;
  // The whole excess |K_d(h)| - pi (1 - h^2) (cap_shadow_area of projected_area.h).
  double excess() const { return has_arc() ? arc_excess(-tk, tk, 2 * psik) : 0.0; }
};

// Radius of K_d(h) at azimuth psi (unit space, unit-space direction d).
double shadow_set_radius(Vec3 d_unit, double h, double psi);

}  // namespace mcref::micrograin
