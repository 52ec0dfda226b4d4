#pragma once
// Isotropic and Henyey-Greenstein phase functions with exact samplers, for
// non-flake SpongeCake layers (projected area sigma(w) = 1).
//
// Directions (see phase_sample.h): wi points toward where the light came from,
// wo toward where it goes, both away from the scattering point. The scattering
// angle is between the propagation directions -wi and wo:
//   cos(theta) = dot(-wi, wo);  g > 0 means forward scattering (wo near -wi).
#include <algorithm>
#include <cmath>

#include "models/core/vec.h"
#include "models/sggx/phase_sample.h"

namespace mcref::sggx {

// 1 / (4 pi).
double isotropic_phase();
// Uniform direction on the sphere; pdf 1/(4 pi), weight = albedo.
PhaseSample sample_isotropic_phase(double albedo, double u1, double u2);

// p(cos) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^(3/2)), cos = dot(-wi, wo); |g| < 1.
inline double hg_phase(double g, Vec3 wi, Vec3 wo) {
  const double c = -dot(wi, wo);
  const double d = 1 + g * g - 2 * g * c;
  return (1 - g * g) / (4 * kPi * d * std::sqrt(d));
}
// Cosine of the scattering angle for uniform u by exact CDF inversion, written
// without division by g (stable at g -> 0, where it tends to 2u - 1).
// CDF of cos in [-1, 1]: P(c) = (1 - g^2)/(2g) [ (1 + g^2 - 2gc)^-1/2 - (1 + g)^-1 ].
// Solving P = u with v = 2u - 1, q = 1 + g v gives
//   c = [v + g (3 + v^2)/2 + g^2 v + g^3 (v^2 - 1)/2] / q^2,
// which is (1 + g^2 - ((1 - g^2)/q)^2)/(2g) expanded so that g cancels.
inline double sample_hg_cos_theta(double g, double u) {
  const double v = 2 * u - 1, q = 1 + g * v;
  const double c = (v + 0.5 * g * (3 + v * v) + g * g * v + 0.5 * g * g * g * (v * v - 1)) / (q * q);
  return std::min(1.0, std::max(-1.0, c));  // (as fmin/fmax, NaN included; vectorises)
}

// Exact HG sample: pdf = hg_phase(g, wi, wo), weight = albedo.
PhaseSample sample_hg_phase(double g, double albedo, Vec3 wi, double u1, double u2);

}  // namespace mcref::sggx
