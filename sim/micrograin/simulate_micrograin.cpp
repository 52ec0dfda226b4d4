// Micrograin fields: for each realization, build the field from its own
// seed, then add one batch to every measure's tables.
#include "sim/experiment/simulate_kinds.h"
#include "sim/micrograin/estimator.h"

namespace mcref {

BatchLoop::Tables micrograin_tables(const Experiment& ex) {
  BatchLoop::Tables tables;
  for (const Measure& m : ex.measures) tables.push_back(estimator_for(m.quantity).make_tables(m, ex));
  return tables;
}

std::vector<Table> simulate_micrograin(const Experiment& ex, const BatchLoop& loop, std::size_t* grains) {
  BatchLoop::Tables tables = micrograin_tables(ex);
  loop.run(ex.run.batches, tables, [&](int b, BatchLoop::Tables& into) {
    const MicrograinField field(ex.micrograin, micrograin_realization_seed(ex.run.seed, static_cast<std::uint64_t>(b)));
    if (grains) *grains = field.grain_count();
    for (std::size_t k = 0; k < ex.measures.size(); ++k) {
      const Measure& m = ex.measures[k];
      const StreamKey key{ex.run.seed, static_cast<std::uint64_t>(b), k};
      estimator_for(m.quantity).add_batch(field, ex, m, key, into[k]);
      loop.progress().advance(work_units(m));
    }
  });
  return flatten(std::move(tables));
}

}  // namespace mcref
