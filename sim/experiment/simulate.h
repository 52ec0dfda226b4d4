#pragma once
// The public entry point of the simulator: experiment -> tables.
#include <atomic>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/parallel/communicator.h"
#include "sim/tally/table.h"

namespace mcref {

struct SimulateOptions {
  int threads = 0;       // 0: use the experiment's run.threads (0 there: all cores)
  bool quiet = false;    // no progress line
  std::string label = "simulate";
  // Ranks the batches are spread over (sim/parallel/batch_loop.h); the
  // tables are complete on rank 0 only.
  const Communicator* ranks = &Communicator::self();
  // The tables to return, by name (empty: all). Those of the others that can
  // be left out are neither held nor computed (slab BRDF tables); the
  // returned tables are the same bits either way. A name the experiment does
  // not write is an error.
  std::vector<std::string> tables;
  // Set from another thread to stop the run: simulate() throws Cancelled
  // (sim/parallel/progress.h) when a measure of a batch is done.
  const std::atomic<bool>* cancel = nullptr;
  // The tables keep every batch's estimates (Table::batch_values), for
  // verdicts that estimate the cells' correlation; 8 bytes per cell and batch.
  bool keep_batch_values = false;
};

struct SimulateSummary {
  double seconds = 0;
  double rays = 0;  // rays traced in all (for the summary line)
  std::size_t grains = 0;  // grains in the last realization
};

// For each realization: builds the geometry from its own seed, then adds one
// batch to every measure's tables. Bit-identical for any thread count.
std::vector<Table> simulate(const Experiment& experiment, const SimulateOptions& options,
                            SimulateSummary* summary = nullptr);

}  // namespace mcref
