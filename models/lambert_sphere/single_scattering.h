#pragma once
// Single scattering of the Lambertian-sphere half-space, exact phase function (d'Eon 2021, Eq. 10).
//
// sr^-1 WITHOUT the cosine. omega_i (toward the light) and omega_o (toward the
// viewer) both point away from the surface, z is the macro normal; mu = cosines.
// phi = phi_o - phi_i: phi = 0 back toward the light, phi = pi the mirror side
// (DESIGN.md; d'Eon uses the same, see fourier_modes.h).
#include "models/core/vec.h"

namespace mcref::lambert_sphere {

// Relative azimuth phi_o - phi_i in (-pi, pi]; 0 if either direction is along z.
double relative_azimuth(const Vec3& wi, const Vec3& wo);

// Eq. 10: f1 = c p(-omega_i . omega_o) / (mu_i + mu_o), with
// -omega_i . omega_o = -mu_i mu_o - sqrt(1-mu_i^2) sqrt(1-mu_o^2) cos(phi).
// 0 if mu_i <= 0 or mu_o <= 0.
double single_scattering(double c, double mu_i, double mu_o, double phi);
double single_scattering(double c, const Vec3& wi, const Vec3& wo);

}  // namespace mcref::lambert_sphere
