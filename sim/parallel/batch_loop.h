#pragma once
// The batch loop of a simulation. Batches are independent realizations, so
// they may run on different ranks: over N ranks, rank r runs the batches
// b = r mod N, each into a fresh copy of the empty tables, and rank 0 merges
// them into the tables in batch order. Adding a one-batch table (0 + x) is
// adding x, so the tables are bit-identical to one process adding every batch
// straight in, for any N. One process runs the batches straight in, unless
// the tables keep their batch values (sim/tally/table.h): then each batch
// too runs into fresh tables that are merged, the same bits.
#include <functional>
#include <vector>

#include "sim/parallel/communicator.h"
#include "sim/parallel/progress.h"
#include "sim/tally/table.h"

namespace mcref {

class BatchLoop {
 public:
  using Tables = std::vector<std::vector<Table>>;  // one list per measure
  // Runs batch `b`, adding one batch to every table of `into`.
  using Batch = std::function<void(int b, Tables& into)>;

  // `batch_work`: the progress work of one batch (advanced here for the
  // batches rank 0 receives; a batch advances its own work as it runs).
  BatchLoop(const Communicator& ranks, Progress& progress, double batch_work, bool keep_batch_values = false)
      : ranks_(ranks), progress_(progress), batch_work_(batch_work), keep_batch_values_(keep_batch_values) {}

  // Runs batches 0..count-1 into `tables` (on rank 0; the other ranks' tables
  // stay empty). `keep_batch_values`: rank 0's tables keep every batch's
  // estimates too.
  void run(int count, Tables& tables, const Batch& batch) const;
  Progress& progress() const { return progress_; }

 private:
  const Communicator& ranks_;
  Progress& progress_;
  double batch_work_;
  bool keep_batch_values_;
};

}  // namespace mcref
