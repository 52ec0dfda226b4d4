#include "sim/slab/walk.h"

#include <algorithm>

#include "sim/slab/escape.h"
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
  for (;;) {
    const Flight f = flight.fly(p, rng);
    if (f == Flight::kLost) return order;
    if (f == Flight::kExitTop) {
      if (!s.next_event || order == 0) out.add(p.d, order, first_class, weight, delta);
      return order;
    }
    if (f == Flight::kExitBottom && !medium.has_substrate()) {
      if (order > 0 ? !s.next_event : s.delta_transmission) out.add(p.d, order, first_class, weight, delta);
      return order;
    }
    // A scattering event: in a layer, or on the substrate.
    if (s.max_order > 0 && order >= s.max_order) return order;
    ++order;
    if (f == Flight::kCollision) {
      if (order == 1) first_class = kClassVolume;
      const ScatterSample sc = flight.scatter(layers[p.layer], p.layer, -p.d, rng);
      if (!sc.valid) return order;
      weight = weight * sc.weight;
      p.d = sc.wo;
      delta = false;
    } else {
      if (order == 1) first_class = kClassSubstrate;
      const SubstrateSample sc = sample_substrate(medium.substrate(), -p.d, rng);
      if (!sc.valid) return order;
      weight = weight * sc.weight;
      p.d = sc.wo;
      delta = delta && sc.specular;
    }
    if (s.next_event)  // before the roulette: its expectation is the same
      if (const double e = escape_probability(medium, p.layer, p.depth, p.d); e > 0)
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
