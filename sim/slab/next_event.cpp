#include "sim/slab/next_event.h"

#include <cmath>

#include "models/core/warp.h"
#include "sim/slab/escape.h"

namespace mcref::volume {

void tally_escape(const SlabMedium& medium, const Photon& p, int order, int first_class, const Rgb& weight, bool delta,
                  Rng& rng, BrdfAccumulator& out) {
  if (const double e = escape_estimate(medium, p, p.d, rng); e > 0) out.add(p.d, order, first_class, weight * e, delta);
}

void tally_next_event_mis(const SlabMedium& medium, const Photon& p, Vec3 wi, const Rgb& before, const Rgb& after,
                          int order, int first_class, Rng& rng, BrdfAccumulator& out) {
  const PhaseFunction& phase = *medium.layers()[p.layer].phase;
  const bool upper_only = medium.has_substrate();
  const double pdf_u = upper_only ? 1 / (2 * kPi) : 1 / (4 * kPi);
  if (const double e = escape_estimate(medium, p, p.d, rng); e > 0) {
    const double f = phase.eval(wi, p.d);
    out.add(p.d, order, first_class, after * (e * f / (f + pdf_u)), false);
  }
  const double u1 = rng.uniform(), u2 = rng.uniform();
  Vec3 u = sample_uniform_sphere(u1, u2);
  if (upper_only) u.z = std::fabs(u.z);
  const double f = phase.eval(wi, u);
  if (!(f > 0)) return;
  if (const double e = escape_estimate(medium, p, u, rng); e > 0)
    out.add(u, order, first_class, before * phase.albedo(wi, u) * (e * f / (f + pdf_u)), false);
}

}  // namespace mcref::volume
