#include "models/sggx/hg_phase.h"

#include <cmath>

#include "models/core/frame.h"
#include "models/core/warp.h"

namespace mcref::sggx {

double isotropic_phase() { return 1.0 / (4 * kPi); }

PhaseSample sample_isotropic_phase(double albedo, double u1, double u2) {
  PhaseSample r;
  r.wo = sample_uniform_sphere(u1, u2);
  r.pdf = isotropic_phase();
  r.weight = albedo;
  r.valid = true;
  return r;
}

double hg_phase(double g, Vec3 wi, Vec3 wo) {
  const double c = -dot(wi, wo);
  const double d = 1 + g * g - 2 * g * c;
  return (1 - g * g) / (4 * kPi * d * std::sqrt(d));
}

// CDF of cos in [-1, 1]: P(c) = (1 - g^2)/(2g) [ (1 + g^2 - 2gc)^-1/2 - (1 + g)^-1 ].
// Solving P = u with v = 2u - 1, q = 1 + g v gives
//   c = [v + g (3 + v^2)/2 + g^2 v + g^3 (v^2 - 1)/2] / q^2,
// which is (1 + g^2 - ((1 - g^2)/q)^2)/(2g) expanded so that g cancels.
double sample_hg_cos_theta(double g, double u) {
  const double v = 2 * u - 1, q = 1 + g * v;
  const double c = (v + 0.5 * g * (3 + v * v) + g * g * v + 0.5 * g * g * g * (v * v - 1)) / (q * q);
  return std::fmin(1.0, std::fmax(-1.0, c));
}

PhaseSample sample_hg_phase(double g, double albedo, Vec3 wi, double u1, double u2) {
  PhaseSample r;
  const double c = sample_hg_cos_theta(g, u1);
  const double s = std::sqrt(std::fmax(0.0, 1 - c * c)), phi = 2 * kPi * u2;
  r.wo = normalize(Frame(-wi).to_world({s * std::cos(phi), s * std::sin(phi), c}));
  r.pdf = hg_phase(g, wi, r.wo);
  r.weight = albedo;
  r.valid = true;
  return r;
}

}  // namespace mcref::sggx
