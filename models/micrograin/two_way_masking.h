#pragma once
// Height-correlated masking from two directions (vNDF paper Eq. 1, 3, 9; issue #15).
//
// A grain point p at unit-space height h (horizontal position 0) is hidden from d
// by another grain of centre c (z = 0) iff the half-line p + t d, t >= 0, comes
// within distance 1 of c. Those c form the convex set K_d(h), the slice z = 0 of
// a capsule; it contains the disc |c| < sqrt(1 - h^2) of grains that would
// contain p. The other centres are Poisson (rho'), so, given p on the surface,
//   G_dist(d, h)    = exp(-rho' (|K_d(h)| - pi (1 - h^2)))            (Eq. 3/9)
//   G_dist(i, o, h) = exp(-rho' (|K_i(h) U K_o(h)| - pi (1 - h^2))),
// the product G_dist(i, h) G_dist(o, h) dropping |K_i(h) ∩ K_o(h)|.
// Radius of K_d(h) at azimuth psi, u = sin theta_d cos(psi - phi_d):
//   r_c = (-u h cos theta_d + sqrt(1 - u^2 - h^2 (sin^2 theta_d - u^2))) / (1 - u^2)
// if r_c u > h cos theta_d (the cylinder part), else sqrt(1 - h^2) (the sphere at p).
// |K_i U K_o| = 1/2 ∮ max(r_i, r_o)^2 dpsi, integrated by adaptive Gauss-Legendre
// between the kinks (where a direction's radius leaves the disc and where
// r_i = r_o), to about 1e-10 absolute. At h = 0 it is pore_shadow_union_area.
//
// Directions: real unit vectors with z > 0; h in [0, 1] (unit-space height).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Radius of K_d(h) at azimuth psi (unit space, unit-space direction d).
double shadow_set_radius(Vec3 d_unit, double h, double psi);

// |K_i(h) U K_o(h)| - pi (1 - h^2) (unit space). For i == o it is cap_shadow_area(i, h).
double cap_shadow_union_area(Vec3 i_unit, Vec3 o_unit, double h);

// G_dist(i, o, h): P(grain point at height h seen from i and from o | on the surface),
// the other grains' masking only (the own grain's is <i.m>+ <o.m>+).
double distant_masking_union(const GrainField& f, Vec3 i, Vec3 o, double h);

}  // namespace mcref::micrograin
