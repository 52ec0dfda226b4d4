#include "sim/parallel/run_chunks.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>

namespace mcref {

Sums run_chunks(std::uint64_t samples, std::size_t sums_size, std::uint64_t key,
                const std::function<void(Rng&, std::uint64_t, Sums&)>& body) {
  // Chunks are handed out in order (one counter) and added to the total in
  // chunk order, so the result does not depend on the thread count. A chunk
  // that finishes before its predecessors waits in `done`; added buffers are
  // recycled, so only a few chunks' sums are alive at a time. (Keeping every
  // chunk's sums until the end made each call fault in megabytes of fresh
  // pages: 4-6 points of the walk's overhead over tracing on 2 threads.)
  const std::uint64_t chunks = (samples + kChunkSamples - 1) / kChunkSamples;
  Sums total(sums_size, 0.0);
  std::mutex m;
  std::map<std::uint64_t, Sums> done;
  std::vector<Sums> spare;
  std::uint64_t next_to_add = 0;
  std::atomic<std::uint64_t> next{0};
  tbb::parallel_for(0, tbb::this_task_arena::max_concurrency(), [&](int) {
    // (A failing chunk cancels the others: stop taking new ones.)
    for (std::uint64_t c; !tbb::is_current_task_group_canceling() && (c = next++) < chunks;) {
      Sums acc;
      {
        const std::lock_guard<std::mutex> lock(m);
        if (!spare.empty()) {
          acc = std::move(spare.back());
          spare.pop_back();
        }
      }
      acc.assign(sums_size, 0.0);
      Rng rng(stream_seed({key, c}));
      body(rng, std::min(kChunkSamples, samples - c * kChunkSamples), acc);
      const std::lock_guard<std::mutex> lock(m);
      done.emplace(c, std::move(acc));
      for (auto it = done.begin(); it != done.end() && it->first == next_to_add; it = done.erase(it), ++next_to_add) {
        for (std::size_t i = 0; i < sums_size; ++i) total[i] += it->second[i];
        spare.push_back(std::move(it->second));
      }
    }
  });
  return total;
}

}  // namespace mcref
