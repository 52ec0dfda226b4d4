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
