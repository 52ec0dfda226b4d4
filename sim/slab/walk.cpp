#include "sim/slab/walk.h"

#include <algorithm>
#include <cmath>

#include "models/core/warp.h"
#include "sim/slab/escape.h"
#include "sim/slab/substrate.h"

namespace mcref::volume {

namespace {

// The next-event estimator with MIS at a volume event (walk.h), the photon at
// the collision with p.d the sampled direction: that direction's escape
// (weight after the event) and a uniform direction's (weight before it),
// balance heuristic.
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

}  // namespace

int walk(const SlabMedium& medium, FreeFlight& flight, const WalkSettings& s, Vec3 wi, Rng& rng,
         BrdfAccumulator& out) {
  Photon p;
  p.d = -wi;
  if (const double period = flight.lateral_period(); period > 0) {
    p.x = rng.uniform() * period;
    p.y = rng.uniform() * period;
  }
  Rgb weight(1.0);
  int order = 0, first_class = kClassVolume;
  bool delta = true;  // no volume event, only specular substrate bounces so far
  const std::vector<MediumLayer>& layers = medium.layers();
  const bool next_event = s.estimator != SlabEstimator::kAnalog;
  for (;;) {
    const Flight f = flight.fly(p, rng);
    if (f == Flight::kLost) return order;
    if (f == Flight::kExitTop) {
      if (!next_event || order == 0) out.add(p.d, order, first_class, weight, delta);
      return order;
    }
    if (f == Flight::kExitBottom && !medium.has_substrate()) {
      if (order > 0 ? !next_event : s.delta_transmission) out.add(p.d, order, first_class, weight, delta);
      return order;
    }
    // A scattering event: in a layer, or on the substrate.
    if (s.max_order > 0 && order >= s.max_order) return order;
    ++order;
    if (f == Flight::kCollision) {
      if (order == 1) first_class = kClassVolume;
      const Vec3 wi_event = -p.d;
      const ScatterSample sc = flight.scatter(layers[p.layer], p.layer, wi_event, rng);
      if (!sc.valid) return order;
      const Rgb before = weight;
      weight = weight * sc.weight;
      p.d = sc.wo;
      delta = false;
      if (s.estimator == SlabEstimator::kNextEventMis)
        tally_next_event_mis(medium, p, wi_event, before, weight, order, first_class, rng, out);
    } else {
      if (order == 1) first_class = kClassSubstrate;
      const SubstrateSample sc = sample_substrate(medium.substrate(), -p.d, rng);
      if (!sc.valid) return order;
      weight = weight * sc.weight;
      p.d = sc.wo;
      delta = delta && sc.specular;
    }
    // Before the roulette: its expectation is the same. (With MIS, volume events are tallied above.)
    if (s.estimator == SlabEstimator::kNextEvent || (next_event && f != Flight::kCollision))
      if (const double e = escape_estimate(medium, p, p.d, rng); e > 0)
        out.add(p.d, order, first_class, weight * e, delta);
    if (order >= s.roulette_from) {
      const double q = std::min(1.0, weight.max());
      if (q < 1) {
        if (rng.uniform() >= q) return order;
        weight = weight / q;
      }
    }
    if (weight.is_zero()) return order;
  }
}

}  // namespace mcref::volume
