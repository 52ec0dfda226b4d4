#pragma once
// One light path through a micrograin layer on its base (issue #3): enters
// from direction i at a uniform point of the tile above the highest grain,
// scatters on grains (micro-BRDF of the grain) and on the base plane
// (micro-BRDF of the base) until it leaves upward. No depth limit: unbiased
// Russian roulette on the RGB throughput once its largest channel m falls below
// kRouletteThreshold (survival m / kRouletteThreshold).
// Every escaping path is scored once, with its scattering order, the place of
// its first event (order-1 class 0 = grain, 1 = base) and whether it is a
// delta lobe (only exact mirror reflections on the flat base: the base's
// mirror image of the light seen through the pores).
#include <cstdint>

#include "models/core/rng.h"
#include "sim/micrograin/micrograin_field.h"
#include "sim/micrograin/micrograin_materials.h"
#include "sim/tally/brdf_tally.h"

namespace mcref {

// Paths keep their weight (no roulette) while its largest channel is above
// this. Measured on tau0 = 0.6 with Lambertian grains 0.8 on a base 0.5:
// against roulette at every event (survival = albedo), 1.3 times as many rays
// per path, and 1.25 times the efficiency (1 / variance x time) of a BRDF
// cell's estimate, 4.8 times that of the albedo.
inline constexpr double kRouletteThreshold = 0.25;

struct WalkCounters {
  std::uint64_t paths = 0;
  std::uint64_t rays = 0;  // intersect_unit calls
};

// wi: real-space incident direction (pointing away from the surface, wi.z > 0).
// max_order > 0 scores only paths of at most that many events (0: unlimited).
void trace_brdf_path(const MicrograinField& f, const MicrograinMaterials& materials, Vec3 wi, int max_order,
                     Rng& rng, BrdfAccumulator& tally, WalkCounters* counters = nullptr);

}  // namespace mcref
