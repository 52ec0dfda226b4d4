#pragma once
// Specular two-sided microflake phase function with an SGGX distribution
// (Heitz 2015 Sec. 4; SpongeCake Eq. 4-5) and its visible-normal sampler.
//
// Directions (see phase_sample.h): wi and wo both point away from the
// scattering point; wi toward the light, wo toward the receiver. A flake with
// normal m sends wi to wo = 2 (wi.m) m - wi, so m = +-h with
// h = normalize(wi + wo).
#include <algorithm>
#include <cmath>

#include "models/sggx/phase_sample.h"
#include "models/sggx/sggx_distribution.h"

namespace mcref::sggx {

// Schlick's approximation f0 + (1 - f0)(1 - c)^5 for a cosine c in [0, 1].
inline double schlick(double f0, double cos_theta) {
  // Clamped by value (NaN -> 0, as std::min(1, std::max(0, .))): std::min's references
  // made temporaries that stopped the wave walk's vectoriser.
  const double c0 = cos_theta > 0 ? cos_theta : 0.0, c = c0 < 1 ? c0 : 1.0;
  const double k = 1 - c, k2 = k * k;
  return f0 + (1 - f0) * k2 * k2 * k;
}
// Flake reflectance F(h) = gamma * Schlick(f0, |wi.h|); one colour channel.
// |wi.h| = |wo.h|, so F is reciprocal. gamma is the flake albedo.
inline double flake_reflectance(double gamma, double f0, Vec3 wi, Vec3 h) {
  return gamma * schlick(f0, std::fabs(dot(wi, h)));
}
// Normalised phase function f_p(wi -> wo) = D(h) / (4 sigma(wi))  (Eq. 4);
// \int f_p dwo = 1. Returns 0 when wi + wo = 0 (h undefined, measure zero).
// (Inline: the wave walk's next-event stage vectorises it.)
inline double specular_flake_phase(const Sggx& s, Vec3 wi, Vec3 wo) {
  const Vec3 sum = wi + wo;
  const double n2 = dot(sum, sum);
  return n2 > 1e-24 ? ndf(s, sum) / (4 * projected_area(s, wi)) : 0.0;  // ndf() normalises its argument
}
// Albedo-weighted phase F(h) f_p(wi -> wo); \int dwo = mean of F over the
// visible normals of wi (= gamma when f0 = 1).
double specular_flake_phase_weighted(const Sggx& s, double gamma, double f0, Vec3 wi, Vec3 wo);
// Samples wo ~ f_p(wi -> .) by drawing a visible normal m of wi and reflecting
// wi about it (Heitz 2015 Sec. 5). pdf = f_p, weight = F(m). u1, u2 in [0, 1).
PhaseSample sample_specular_flake_phase(const Sggx& s, double gamma, double f0, Vec3 wi,
                                        double u1, double u2);

}  // namespace mcref::sggx
