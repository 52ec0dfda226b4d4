#pragma once
// Dynamic scheduling of a dataset's entries over the ranks of a job: rank 0
// keeps the queue of pending entries, and a rank that finishes an entry asks
// rank 0 for the next one, so a few expensive entries do not hold up the rest.
// Rank 0 computes entries too, on a thread of its own, while its main thread
// answers the others (only the main thread talks MPI). Each entry is computed
// once, by one rank; what it computes depends on the entry alone, so the
// assignment does not change any result.
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/parallel/communicator.h"

namespace mcref {

struct ScheduleSummary {
  std::int64_t computed = 0;  // entries computed by the whole job (on rank 0)
  double rays = 0;            // their rays (on rank 0)
};

// Computes the first `limit` entries of `queue` (all if limit < 0; the queue
// of rank 0 counts) with `compute(index)`, which returns the entry's rays.
// On rank 0, `done(index, rays)` is called on the calling thread as each
// entry finishes on any rank. One process: the entries in queue order.
ScheduleSummary schedule_entries(const Communicator& ranks, const std::vector<std::int64_t>& queue,
                                 std::int64_t limit, const std::function<double(std::int64_t)>& compute,
                                 const std::function<void(std::int64_t, double)>& done);

}  // namespace mcref
