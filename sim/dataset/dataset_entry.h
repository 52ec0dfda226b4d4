#pragma once
// One entry of a dataset: its parameter values (a deterministic function of
// the dataset seed and the entry index) applied to the base experiment.
//
// Entry index i = grid_index * per_point + sample, the grid index running
// over the grid parameters in the order listed (the last one fastest).
// Sampled parameter k of entry i draws from its own stream,
// stream_seed(dataset seed, "param", i, k); the entry is simulated with
// run.seed = stream_seed(dataset seed, "entry", i) / 2 (whatever the base's
// run.seed), so entries do not depend on shards, threads or each other.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/dataset/dataset_config.h"
#include "sim/experiment/experiment.h"

namespace mcref {

struct EntryPlan {
  std::int64_t index = 0;
  std::uint64_t seed = 0;                // run.seed of the entry's simulation
  std::vector<double> columns;           // one per parameter column; NaN where the parameter does not apply
  std::vector<std::string> assignments;  // "key=value" in the order applied (counts first), then run.seed
  toml::table experiment;                // the base experiment with the entry's values applied
};

EntryPlan plan_entry(const DatasetConfig& config, std::int64_t index);

// Validates the entry's experiment; a bad value is a ConfigError naming the
// dataset file, the entry, its assignments and the experiment key.
Experiment entry_experiment(const DatasetConfig& config, const EntryPlan& plan);

// Checks every value the parameters can take, whichever entries a run computes:
// each grid value and choice, and both ends of each sampled range, applied to
// entry 0 with every count at its largest (so that every parameter applies). A
// bad one is a ConfigError naming the dataset file, the parameter's key and the
// value. Values bad only in combination are found where an entry is planned.
void check_parameter_values(const DatasetConfig& config);

}  // namespace mcref
