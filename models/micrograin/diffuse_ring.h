#pragma once
// The ring integral of the G_dist diffuse geometry (vNDF paper Eq. 1 and 7,
// issue #15 part 4): over the unit-space normals m' = (st cos a, st sin a, h)
// of one polar ring, with M m' = (st beta_x cos a, st beta_y sin a, h),
//   ∫_0^2pi <i.m>+ <o.m>+ T_i T_o |M m'| da,  m = M m' / |M m'|,
// T_d = 1 - F_dielectric(<d.m>, ior) (ior <= 1: T = 1). With
// P_d(a) = (M m').d = A + B cos a + C sin a the integrand is
// P_i P_o T_i T_o / |M m'|, zero where either sinusoid is negative.
//
// Isotropic grains without Fresnel: in closed form (clipped_cosines.h).
// Otherwise the integrand is analytic on the real line except where a
// sinusoid changes sign (the Fresnel factor's branch points and poles, and the
// zeros of |M m'|^2, lie off the real axis or at <d.m> < 0), so:
// - no zeros on the ring (both sinusoids positive): the periodic trapezoid
//   rule, 32, 64, ... points until two successive ones agree to rel_tol;
// - else, between the exact zeros of P_i and P_o (clipped_cosines.h): a
//   24-point Gauss-Legendre rule per piece, accepted where a 16-point rule
//   agrees with it to rel_tol of the ring (or to the rounding of the
//   integrand, for rings clipped to slivers); only pieces where they disagree
//   are halved.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// The ring at unit-space height h = cos theta', st = sin theta'; its error is
// about rel_tol of the ring's value or far below (tests/models/test_micrograin_diffuse_ring.cpp).
double diffuse_ring_integral(const GrainField& f, Vec3 i, Vec3 o, double ior, double h, double st,
                             double rel_tol = 1e-10);

}  // namespace mcref::micrograin
