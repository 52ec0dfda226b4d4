#pragma once
// Visibility of a base point from two directions (LRPB23 Eq. 22-24; issue #15).
//
// Grain centres are Poisson with unit-space density rho' = -ln(1 - tau0)/pi.
// A base point is hidden from d by the grain of centre c iff c lies in
//   K_d = unit disc  U  {half of the ellipse of semi-axes (1/cos theta'_d, 1)
//                         on the side of d's azimuth}           (unit space),
// so P(seen from d) = exp(-rho' |K_d|) (Eq. 22) and
//   P(seen from i and o) = exp(-rho' |K_i U K_o|).
// In polar coordinates about the point, with u_d(psi) = sin theta'_d cos(psi - phi'_d),
// K_d has radius r_d^2 = 1 / (1 - u_d^2) where u_d > 0 and 1 elsewhere, so
// |K_i U K_o| = pi + 1/2 ∮ U^2 / (1 - U^2) dpsi,  U = max(u_i, u_o, 0).
// u_i > u_o on the half-plane psi.(d_i - d_o)_h > 0: each half is one
// direction's integrand, integrated in closed form with
// ∫ dx / (cos^2 theta cos^2 x + sin^2 x) = atan(tan x / cos theta) / cos theta.
// Eq. 23/24 use the product V(i) V(o) instead, which drops |K_i ∩ K_o|.
//
// Directions: real unit vectors with z > 0 (theta' < pi/2), mapped to the unit space.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// |K_i U K_o| - pi (unit space, unit-space directions): the area of centre
// positions outside the unit disc whose grain hides the point from i or o.
// Equals (pi/2)(1/cos theta'_d - 1) for i == o.
double pore_shadow_union_area(Vec3 i_unit, Vec3 o_unit);

// V_p(i, o) = P(seen from i and o | the point lies in a pore) = exp(-rho' (|K_i U K_o| - pi)):
// the quantity of the simulated pore_visibility table.
double pore_visibility_union(const GrainField& f, Vec3 i, Vec3 o);

// The product of Eq. 23/24 for comparison: V(i) V(o), V(d) = (1 - tau+(d)) / (1 - tau0) (Eq. 22).
double pore_visibility_product(const GrainField& f, Vec3 i, Vec3 o);

// Base term weight of vNDF Eq. 1: P(base point in a pore and seen from i and o)
// = (1 - tau0) V_p(i, o); the union form of 1 - w+(i, o) (LRPB23 Eq. 24).
double base_visibility_union(const GrainField& f, Vec3 i, Vec3 o);

}  // namespace mcref::micrograin
