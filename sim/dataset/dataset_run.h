#pragma once
// Running a dataset: every entry of a shard simulated once, kept as an atomic
// per-entry part file in OUTPUT.parts/ (so an interrupted run resumes without
// losing finished entries), and assembled into OUTPUT atomically, in index
// order, while the later entries are computed (sim/dataset/entry_assembler.h); and
// merging shard files into the file a single-process run would have written,
// byte for byte.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_file.h"
#include "sim/parallel/communicator.h"

namespace mcref {

struct DatasetRunOptions {
  std::string output;
  int shard = 0, shards = 1;     // --shard K/N: entries with index % N == K
  int threads = 0;               // 0: the experiment's run.threads (0 there: all cores)
  bool quiet = false;
  std::int64_t stop_after = -1;  // compute at most this many new entries, then stop without assembling
  bool lean = false;             // OUTPUT in lean storage (the parts keep the sums, so resume works)
  // Ranks the entries are spread over (sim/dataset/entry_scheduler.h): each
  // writes the parts it computes; rank 0 scans the parts and assembles OUTPUT
  // on a thread of its own as they are finished.
  const Communicator* ranks = &Communicator::self();
};

struct DatasetRunSummary {
  std::int64_t entries = 0;   // entries of this shard
  std::int64_t computed = 0;  // simulated by this run (all ranks)
  std::int64_t reused = 0;    // found finished in OUTPUT.parts/
  bool complete = false;      // OUTPUT written (or already up to date)
  bool up_to_date = false;    // OUTPUT already held this shard
  double seconds = 0, rays = 0;
};

// The header every file of this dataset carries (shard: "all", "K/N" or "part").
DatasetHeader dataset_header(const DatasetConfig& config, const std::string& shard);

// Validates every entry first (a bad entry is a ConfigError; nothing is
// written). The summary is the job's on rank 0.
DatasetRunSummary run_dataset(const DatasetConfig& config, const DatasetRunOptions& options);

// Combines shard files (same dataset, no overlaps, every entry present, none
// lean) into `output` (lean storage if `lean`); returns the number of entries.
std::int64_t merge_datasets(const std::vector<std::string>& inputs, const std::string& output, bool quiet,
                            bool lean = false);

}  // namespace mcref
