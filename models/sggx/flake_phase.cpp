#include "models/sggx/flake_phase.h"

#include <cmath>

namespace mcref::sggx {

double specular_flake_phase_weighted(const Sggx& s, double gamma, double f0, Vec3 wi, Vec3 wo) {
  const Vec3 sum = wi + wo;
  const double n2 = dot(sum, sum);
  if (!(n2 > 1e-24)) return 0;
  const Vec3 h = sum / std::sqrt(n2);
  return flake_reflectance(gamma, f0, wi, h) * ndf(s, h) / (4 * projected_area(s, wi));
}

PhaseSample sample_specular_flake_phase(const Sggx& s, double gamma, double f0, Vec3 wi,
                                        double u1, double u2) {
  PhaseSample r;
  const Vec3 m = sample_visible_normal(s, wi, u1, u2);
  const double c = dot(wi, m);
  r.wo = normalize(m * (2 * c) - wi);
  r.pdf = specular_flake_phase(s, wi, r.wo);
  if (!(r.pdf > 0)) return r;
  r.weight = flake_reflectance(gamma, f0, wi, m);
  r.valid = true;
  return r;
}

}  // namespace mcref::sggx
