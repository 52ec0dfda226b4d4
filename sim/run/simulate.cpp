#include "sim/run/simulate.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <memory>

#include "sim/estimators/estimator.h"
#include "sim/run/progress.h"

namespace mcref {

namespace {
// Stream tag of the geometry of a realization (measures use their index).
constexpr std::uint64_t kGeometryStream = 0xFFFFFFFFull;
}  // namespace

std::vector<Table> simulate(const Experiment& ex, const SimulateOptions& options, SimulateSummary* summary) {
  const int threads = options.threads > 0 ? options.threads
                                          : (ex.run.threads > 0 ? ex.run.threads : tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  std::vector<std::vector<Table>> tables;
  double work_per_batch = 0;
  for (const Measure& m : ex.measures) {
    tables.push_back(estimator_for(m.quantity).make_tables(m, ex.micrograin));
    const double dirs = std::max<std::size_t>(1, m.theta_i.size() * std::max<std::size_t>(1, m.phi_i.size()));
    work_per_batch += static_cast<double>(m.samples) * dirs;
  }
  Progress progress(options.label, work_per_batch * ex.run.batches, options.quiet);
  std::size_t grains = 0;
  for (int b = 0; b < ex.run.batches; ++b) {
    const MicrograinField field(ex.micrograin, stream_seed({ex.run.seed, static_cast<std::uint64_t>(b), kGeometryStream}));
    grains = field.grain_count();
    for (std::size_t k = 0; k < ex.measures.size(); ++k) {
      const Measure& m = ex.measures[k];
      const StreamKey key{ex.run.seed, static_cast<std::uint64_t>(b), k};
      estimator_for(m.quantity).add_batch(field, m, key, tables[k]);
      const double dirs = std::max<std::size_t>(1, m.theta_i.size() * std::max<std::size_t>(1, m.phi_i.size()));
      progress.advance(static_cast<double>(m.samples) * dirs);
    }
  }
  progress.finish();
  if (summary) {
    summary->seconds = progress.elapsed_seconds();
    summary->rays = work_per_batch * ex.run.batches;
    summary->grains = grains;
  }
  std::vector<Table> out;
  for (auto& group : tables)
    for (auto& t : group) out.push_back(std::move(t));
  return out;
}

}  // namespace mcref
