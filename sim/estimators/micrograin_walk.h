#pragma once
// One light path through a micrograin layer on its base (issue #3): enters
// from direction i at a uniform point of the tile above the highest grain,
// scatters on grains (micro-BRDF of the grain) and on the base plane
// (micro-BRDF of the base) until it leaves upward. No depth limit: unbiased
// Russian roulette on the RGB throughput once its largest channel m falls below
// 0.25 (survival m / 0.25).
// Every escaping path is scored once, with its scattering order, the place of
// its first event (order-1 class 0 = grain, 1 = base) and whether it is a
// delta lobe (only exact mirror reflections on the flat base: the base's
// mirror image of the light seen through the pores).
#include <cstdint>

#include "sim/core/rng.h"
#include "sim/geometry/micrograin_field.h"
#include "sim/materials/micrograin_materials.h"
#include "sim/tally/brdf_tally.h"

namespace mcref {

struct WalkCounters {
  std::uint64_t paths = 0;
  std::uint64_t rays = 0;  // intersect_unit calls
};

// wi: real-space incident direction (pointing away from the surface, wi.z > 0).
// max_order > 0 scores only paths of at most that many events (0: unlimited).
void trace_brdf_path(const MicrograinField& f, const MicrograinMaterials& materials, Vec3 wi, int max_order,
                     Rng& rng, BrdfAccumulator& tally, WalkCounters* counters = nullptr);

}  // namespace mcref
