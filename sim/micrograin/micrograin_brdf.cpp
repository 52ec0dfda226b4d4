// brdf on micrograin fields: light transport with grain and base micro-BRDFs
// (issue #3). For each incident direction, `samples` paths per batch (one
// batch = one realization of the field) enter at uniform points of the tile;
// the escaping energy is binned by brdf_tally (equal solid angle in
// cos theta_o x relative azimuth, folded for isotropic fields), split by order:
// order1_grain, order1_base, order2, order3, order4plus, per RGB channel. The
// base's exact mirror reflection of the light seen through the pores is a
// delta lobe: its energy is in <name>_delta, never in the bins, so the binned
// tables stay densities.
#include <cstdio>

#include "sim/experiment/config_error.h"
#include "sim/micrograin/estimator.h"
#include "sim/micrograin/micrograin_walk.h"
#include "sim/tally/brdf_batch.h"

namespace mcref {

namespace {

BrdfLayout layout_of(const Measure& m, const MicrograinGeometry& g) {
  BrdfLayout l;
  l.theta_o_bins = m.theta_o_bins;
  l.phi_bins = m.phi_bins;
  l.folded = !g.anisotropic();
  l.transmission = false;
  l.order1_classes = {"grain", "base"};
  return l;
}

}  // namespace

Estimator micrograin_brdf_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment& ex) -> std::vector<Table> {
    if (!ex.materials.configured)
      throw ConfigError(ex.file, "material",
                        "is required for quantity \"brdf\": [material.grain] and [material.base] with a type each");
    std::vector<Table> tables = make_brdf_tables(m.name, m.theta_i, m.phi_i, layout_of(m, ex.micrograin));
    for (Table& t : tables) {
      t.attributes["grain_material"] = ex.materials.grain.name();
      t.attributes["base_material"] = ex.materials.base.name();
      t.attributes["order1_classes"] = "grain: first event on a grain; base: first event on the base plane";
      char roulette[96];
      std::snprintf(roulette, sizeof roulette, "unbiased, once the largest RGB throughput m < %g, survival m / %g; no depth limit",
                    kRouletteThreshold, kRouletteThreshold);
      t.attributes["russian_roulette"] = roulette;
      if (m.max_order > 0) t.attributes["max_order"] = std::to_string(m.max_order) + " (higher orders not scored)";
    }
    return tables;
  };
  e.add_batch = [](const MicrograinField& f, const Experiment& ex, const Measure& m, const StreamKey& key,
                   std::vector<Table>& tables) {
    const BrdfLayout l = layout_of(m, f.geometry());
    BrdfBatch batch(l, static_cast<double>(m.samples), tables);
    std::uint64_t dir = 0;
    for (double theta : m.theta_i)
      for (double phi : m.phi_i) {
        const Vec3 wi = incident_direction(theta, phi);
        batch.add(dir, run_chunks(m.samples, l.sums_size(), key.with(dir), [&](Rng& rng, std::uint64_t n, Sums& s) {
          BrdfAccumulator acc(l, phi, s);
          for (std::uint64_t k = 0; k < n; ++k) trace_brdf_path(f, ex.materials, wi, m.max_order, rng, acc);
        }));
        ++dir;
      }
    batch.close();
  };
  return e;
}

}  // namespace mcref
