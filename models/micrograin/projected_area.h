#pragma once
// Projected area sigma(i, h) of one unit-space grain cap (vNDF paper Eq. 5,
// Fig. 2; LRPB24): the area that the part of a unit hemisphere above height h
// covers on the plane z = h when seen along the unit-space direction i, i.e.
// the cross-section disc sigma(n, h) = pi (1 - h^2) plus the shadow sigma_s
// the cap casts beyond that disc (zero when h >= sin theta_i).
//
// All functions here are in the unit space (grains are unit hemispheres); map
// real directions with to_unit_direction first. Ranges: theta_i in [0, pi/2)
// (polar angle of the unit-space direction), h in [0, 1].
#include "models/core/vec.h"

namespace mcref::micrograin {

// sigma(n, h) = pi (1 - h^2): the cap's cross-section at height h.
double cap_cross_section(double h);

// Shadow term sigma_s(i, h): the excess of the shadow set K_i(h) over the disc,
// the sector of the ellipse arc beyond it minus the disc's (shadow_set.h). It is the
// closed form of the first author's renderer (LilTracer, src/lt/brdf/micrograin.cpp,
// as restated in papers/README.md), with sin theta_m = sqrt(1 - h^2),
// cos phi_q = -1/(tan theta_i tan theta_m), q = sin theta_m (cos phi_q, sin phi_q),
// e_x = h tan theta_i:
//   sigma_e = acos(clamp(-(q_x - e_x) cos theta_i, 0, 1)) / cos theta_i  (ellipse sector)
//   sigma_t = |e_x q_y|                                                 (two triangles)
//   sigma_c = (pi - phi_q) sin^2 theta_m                                 (disc sector)
//   sigma_s = max(sigma_e - sigma_t - sigma_c, 0), and 0 if h >= sin theta_i,
// i.e. sigma_e = t_k / cos theta_i, sigma_t = h tan theta_i sin t_k and sigma_c =
// psi_k (1 - h^2) in shadow_set.h's terms, evaluated with atan2 instead of acos: the acos form lost up to 8e-9 (absolute)
// where h -> sin theta_i (2 % at theta_i = 89.99 deg, 1 - h / sin theta_i = 1e-7).
double cap_shadow_area(double theta_i, double h);
// Same from a unit-space direction i_unit (i_unit.z > 0). Both are accurate to
// ~1e-13 relative for their inputs up to theta_i = pi/2 - 1e-9
// (tests/models/test_micrograin_projected_area.cpp); theta_i's takes cos theta_i
// of its argument, so near grazing it inherits the argument's rounding:
// pi/2 - delta in double is off by up to 1e-16, i.e. ~1e-16 / delta relative in
// cos theta_i and in sigma_s. Where the direction's z is known, use i_unit, as
// models/micrograin does.
double cap_shadow_area(Vec3 i_unit, double h);

// vNDF Eq. 5: sigma(i, h) = sigma(n, h) + sigma_s(i, h).
// At h = 0: sigma(i, 0) = (pi/2)(1 + 1/cos theta_i).
double projected_cap_area(double theta_i, double h);
double projected_cap_area(Vec3 i_unit, double h);

// Independent numerical evaluation of sigma(i, h): the cap above h is the union
// of the horizontal discs of radius sqrt(1 - z^2) at heights z in [h, 1]; seen
// along i (azimuth 0) and projected on z = h, the disc at z is centred at
// x = -(z - h) tan theta_i. For each x the union's extent in y is
// [-Y(x), Y(x)], Y(x)^2 = max_z (1 - z^2 - (x + (z - h) tan theta_i)^2), a
// concave quadratic maximised in closed form; the area 2 ∫ Y(x) dx is
// integrated by composite Gauss–Legendre (`panels` panels of 16 points per
// piece) after a cosine substitution that removes the square-root end points.
double projected_cap_area_numeric(double theta_i, double h, int panels = 64);

}  // namespace mcref::micrograin
