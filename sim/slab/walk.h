#pragma once
// One light path through a slab (analog random walk): enters the top face
// along -wi, free flights (sim/slab/free_flight.h), phase-function
// scattering in the layers, substrate bounces, until it leaves through the
// top (reflection) or the bottom face (transmission, no substrate).
// Orders count scattering events (volume and substrate); order-1 paths are
// classed by where their event happened (0 = volume, 1 = substrate).
// Paths that leave without any volume event and with only specular substrate
// bounces are delta lobes: the unscattered transmission (order 0, in the
// totals only, if delta_transmission) and the mirror reflection of
// a smooth conductor. Russian roulette from order 2 on keeps it unbiased;
// max_order > 0 drops paths that would scatter more often (the paper's cap).
//
// Estimators of the escaping light (WalkSettings::estimator):
//  - analog: a path is tallied where it leaves, with its weight;
//  - next event: at every event (volume or substrate), once the new direction
//    wo is sampled, the path's escape along wo without another collision is
//    tallied with its probability, weight x exp(-tau to the face) (sim/slab/escape.h),
//    in the bin of wo and the order of that event; the path then flies on as
//    in the analog walk, and where it actually leaves it is not tallied again.
//    Each event's escape is replaced by its expectation given wo, so the
//    tables' expectations are the same; only the unscattered light (order 0)
//    stays analog. Through layers varying in depth only it draws no extra
//    random numbers, so it walks the same paths as the analog walk from the
//    same stream; through laterally varying OpenVDB layers the escape
//    probability is itself estimated without bias (residual ratio tracking,
//    escape_estimate), with random numbers drawn from the path's stream, so
//    those paths differ from the analog walk's.
//  - next event with MIS: the same, and at volume events a second direction u,
//    uniform over the directions that can leave (the sphere; the upper
//    hemisphere over a substrate), tallied with weight x albedo(wi, u) f_p(wi, u)
//    exp(-tau(u)) / (f_p(wi, u) + pdf_u); the sampled direction's escape is
//    then weighted by f_p / (f_p + pdf_u) (balance heuristic, Veach 1997 Eq. 9.10).
#include <cstdint>

#include "models/core/rng.h"
#include "sim/slab/free_flight.h"
#include "sim/tally/brdf_tally.h"

namespace mcref::volume {

struct WalkSettings {
  int max_order = 0;             // 0: unlimited
  bool delta_transmission = true;
  int roulette_from = 2;         // Russian roulette once order >= this
  SlabEstimator estimator = SlabEstimator::kAnalog;  // (above); next event: see escape_unsupported()
};

inline constexpr int kClassVolume = 0, kClassSubstrate = 1;

// Returns the number of scattering events of the path.
int walk(const SlabMedium& medium, FreeFlight& flight, const WalkSettings& s, Vec3 wi, Rng& rng,
         BrdfAccumulator& out);

}  // namespace mcref::volume
