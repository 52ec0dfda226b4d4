#include "sim/slab/walk.h"

#include <algorithm>
#include <cmath>

#include "sim/slab/next_event.h"
#include "sim/slab/substrate.h"

namespace mcref::volume {

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
      if (tallies_exit(s, true, order)) out.add(p.d, order, first_class, weight, delta);
      return order;
    }
    if (f == Flight::kExitBottom && !medium.has_substrate()) {
      if (tallies_exit(s, false, order)) out.add(p.d, order, first_class, weight, delta);
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
      tally_escape(medium, p, order, first_class, weight, delta, rng, out);
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
