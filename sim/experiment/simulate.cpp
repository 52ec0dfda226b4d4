#include "sim/experiment/simulate.h"

#include <tbb/global_control.h>

#include <algorithm>

#include "sim/experiment/config_error.h"
#include "sim/experiment/simulate_kinds.h"
#include "sim/experiment/table_plan.h"

namespace mcref {

double work_units(const Measure& m) {
  const std::size_t dirs = m.theta_i.size() * std::max<std::size_t>(1, m.phi_i.size());
  return static_cast<double>(m.samples) * static_cast<double>(std::max<std::size_t>(1, dirs));
}

std::vector<Table> flatten(std::vector<std::vector<Table>>&& per_measure) {
  std::vector<Table> out;
  for (auto& group : per_measure)
    for (auto& t : group) out.push_back(std::move(t));
  return out;
}

std::vector<Table> simulate(const Experiment& ex, const SimulateOptions& options, SimulateSummary* summary) {
  const int threads = effective_threads(ex, options.threads);
  const Communicator& ranks = *options.ranks;
  check_table_names(ex, options.tables, "SimulateOptions", "tables");
  // Before anything is allocated, on every rank (each holds the tables, and
  // its node has its own budget); and every rank simulates rank 0's
  // experiment (another file at the same path on a node would add its
  // batches to rank 0's tables unseen).
  std::string text = ex.text;
  ranks.broadcast(text);
  check_on_every_rank(ranks, [&] {
    if (text != ex.text)
      throw ConfigError(ex.file, "", "differs from rank 0's copy of the experiment (another file at this path on this node?); "
                                     "every rank must read the same experiment");
    check_memory(ex, threads, options.keep_batch_values);
  });
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  double work = 0;
  for (const Measure& m : ex.measures) work += work_units(m);
  work *= ex.run.batches;
  Progress progress(options.label, work, options.quiet || !ranks.root());
  progress.stop_when(options.cancel);
  const BatchLoop loop(ranks, progress, work / ex.run.batches, options.keep_batch_values);
  std::size_t grains = 0;
  std::vector<Table> out = ex.kind == "micrograin" ? simulate_micrograin(ex, loop, &grains)
                           : ex.kind == "slab"     ? simulate_slab(ex, loop, options.tables)
                                                   : simulate_spheres(ex, loop);
  progress.finish();
  if (!options.tables.empty())  // in the experiment's order
    out.erase(std::remove_if(out.begin(), out.end(),
                             [&](const Table& t) {
                               return std::find(options.tables.begin(), options.tables.end(), t.name) == options.tables.end();
                             }),
              out.end());
  if (summary) {
    summary->seconds = progress.elapsed_seconds();
    summary->rays = work;
    summary->grains = grains;
  }
  return out;
}

}  // namespace mcref
