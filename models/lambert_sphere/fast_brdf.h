#pragma once
// Fast variant of the Lambertian-sphere BRDF (d'Eon 2021, Eq. 41):
//   f_r = max(0, f1 + 0.0151829 (c - 0.249978) (|phi| + sqrt(mu_i mu_o)) / (acos(S)/S + 0.113706)
//                 + 0.234459 k_d^1.85432),
// S = sqrt(1 - mu_i^2) sqrt(1 - mu_o^2), k_d from Eq. 40, f1 the exact single
// scattering (Eq. 10). sr^-1 without the cosine; phi = phi_o - phi_i in
// [-pi, pi], phi = 0 back toward the light (DESIGN.md). At S = 0 the middle
// term's limit 0 is used (acos(S)/S -> inf).
#include "models/core/vec.h"

namespace mcref::lambert_sphere {

double brdf_fast(double c, double mu_i, double mu_o, double phi);
double brdf_fast(double c, const Vec3& wi, const Vec3& wo);

}  // namespace mcref::lambert_sphere
