#pragma once
// The next-event tallies of one event (walk.h's estimators), shared by the
// scalar walk (walk.cpp) and the wave walk (wave_walk.cpp): the photon at the
// event's point, p.d the direction just sampled.
#include "models/core/rgb.h"
#include "models/core/rng.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/walk.h"
#include "sim/tally/brdf_tally.h"

namespace mcref::volume {

// Whether a path leaving the stack (through the top, or through the bottom
// without a substrate) is tallied where it leaves: always by the analog
// estimator; by the next-event ones only unscattered (order 0, which they do
// not estimate), through the bottom only if delta_transmission.
inline bool tallies_exit(const WalkSettings& s, bool top, int order) {
  const bool next_event = s.estimator != SlabEstimator::kAnalog;
  return top ? !next_event || order == 0 : order > 0 ? !next_event : s.delta_transmission;
}

// next event: weight x the escape probability along p.d (sim/slab/escape.h),
// in p.d's bin and the event's order.
void tally_escape(const SlabMedium& medium, const Photon& p, int order, int first_class, const Rgb& weight, bool delta,
                  Rng& rng, BrdfAccumulator& out);

// next event with MIS at a volume event (wi the incident direction): p.d's
// escape with the weight after the event and a uniform direction's with the
// weight before it (times the albedo), balance heuristic.
void tally_next_event_mis(const SlabMedium& medium, const Photon& p, Vec3 wi, const Rgb& before, const Rgb& after,
                          int order, int first_class, Rng& rng, BrdfAccumulator& out);

}  // namespace mcref::volume
