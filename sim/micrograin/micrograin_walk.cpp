#include "sim/micrograin/micrograin_walk.h"

#include <algorithm>
#include <cmath>

namespace mcref {

void trace_brdf_path(const MicrograinField& f, const MicrograinMaterials& mat, Vec3 wi, int max_order, Rng& rng,
                     BrdfAccumulator& tally, WalkCounters* counters) {
  if (counters) ++counters->paths;
  std::uint64_t* rays = counters ? &counters->rays : nullptr;
  Vec3 d = -wi;  // not unit length after a Lambertian event (normalised where scored)
  Vec3 o = {rng.uniform() * f.unit_side_x(), rng.uniform() * f.unit_side_y(), 1.0};
  std::uint32_t start = MicrograinField::kNoGrain;
  Rgb throughput(1.0);
  int order = 0, first_class = 0;
  bool delta = true;  // every event so far was an exact mirror reflection on the base
  for (;;) {
    if (rays) ++*rays;
    // A ray leaving a grain does not hit that grain again (the field skips self-hits).
    const Hit h = f.intersect_unit(o, f.to_unit(d), start);
    if (h.kind == Hit::Kind::Escape) {
      if (order > 0) tally.add(d * (1 / length(d)), order, first_class, throughput, delta);
      return;
    }
    if (max_order > 0 && order >= max_order) return;
    ++order;
    const bool grain = h.kind == Hit::Kind::Grain;
    if (order == 1) first_class = grain ? 0 : 1;
    const MicroBrdfSample s = sample_micro_brdf(grain ? mat.grain : mat.base, -d, h.normal, rng);
    if (s.absorbed) return;
    throughput = throughput * s.weight;
    delta = delta & s.delta & !grain;  // (no branches: grain or not is random)
    d = s.wo;
    // Unbiased Russian roulette on the largest channel, once it falls below
    // kRouletteThreshold; survivors carry that weight again.
    const double m = throughput.max();
    if (m <= 0) return;
    if (m < kRouletteThreshold) {
      const double q = m / kRouletteThreshold;
      if (rng.uniform() >= q) return;
      throughput = throughput / q;
    }
    o = h.unit_position;
    start = h.grain;  // kNoGrain on the base
  }
}

}  // namespace mcref
