// p1: density of the distance from a uniform point of the plane to the
// closest grain centre (LRPB23 Eq. 8-10, Fig. 4a), in unit space (distances
// in grain radii; for isotropic grains these are real distances / radius).
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator p1_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    Table t(m.name, "p1", {Axis::uniform_bins("r", "grain radius", 0.0, m.r_max, m.r_bins)});
    t.units = "1/grain radius";
    t.description = "density of the distance from a uniform point to the closest grain centre (bin average)";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const Axis& r = tables[0].axes[0];
    const Sums counts = run_chunks(m.samples, r.size(), key.with(0), [&](Rng& rng, std::uint64_t n, Sums& acc) {
      for (std::uint64_t s = 0; s < n; ++s) {
        const double d = f.nearest_centre_distance(rng.uniform() * f.unit_side_x(), rng.uniform() * f.unit_side_y());
        const int b = r.find_bin(d);
        if (b >= 0) acc[b] += 1;
      }
    });
    std::vector<double> est(r.size());
    for (std::size_t b = 0; b < r.size(); ++b)
      est[b] = counts[b] / (static_cast<double>(m.samples) * (r.upper(b) - r.lower(b)));
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
