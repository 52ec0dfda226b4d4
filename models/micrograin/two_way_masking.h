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
// K_d(h) is the disc |c| < sqrt(1 - h^2) and, beyond it, an arc of an ellipse
// E_d (shadow_set.h). |K_i U K_o| - pi (1 - h^2) in closed form: the circle of
// azimuths is cut at each set's kinks (where its arc leaves the disc) and where
// the two arcs cross; between cuts the union's boundary is the disc's (excess 0)
// or one arc's, whose sector is closed form. The crossings are the sign changes,
// on E_i's arc, of E_o's implicit equation at E_i's point of parameter t, a
// trigonometric polynomial of degree 2: isolated by bisection certified with a
// bound on its second derivative (a root pair can hide only in a piece narrower
// than 1e-9 in t, or where the two ellipses agree to rounding), then polished
// by Newton. At h = 0 it is pore_shadow_union_area.
//
// Directions: real unit vectors with z > 0; h in [0, 1] (unit-space height).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// |K_i(h) U K_o(h)| - pi (1 - h^2) (unit space). For i == o it is cap_shadow_area(i, h).
double cap_shadow_union_area(Vec3 i_unit, Vec3 o_unit, double h);

// G_dist(i, o, h): P(grain point at height h seen from i and from o | on the surface),
// the other grains' masking only (the own grain's is <i.m>+ <o.m>+).
double distant_masking_union(const GrainField& f, Vec3 i, Vec3 o, double h);

}  // namespace mcref::micrograin
