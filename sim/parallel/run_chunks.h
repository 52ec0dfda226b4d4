#pragma once
// Deterministic chunked parallel sampling, shared by every microstructure's
// estimators: a fixed split into chunks, one counter-seeded RNG per chunk,
// chunk sums merged in chunk order, so results are the same for any thread count.
#include <cstdint>
#include <functional>
#include <vector>

#include "models/core/rng.h"

namespace mcref {

// Identifies the random stream of one (run, realization, measure).
struct StreamKey {
  std::uint64_t run_seed;
  std::uint64_t realization;
  std::uint64_t measure;
  std::uint64_t with(std::uint64_t direction) const { return stream_seed({run_seed, realization, measure, direction}); }
};

// Accumulator of one chunk: plain sums, merged element-wise in chunk order.
using Sums = std::vector<double>;

// Runs `samples` samples in fixed chunks of kChunkSamples; chunk c draws from
// Rng(stream_seed({key, c})) and adds into its own Sums; the chunk sums are
// merged in chunk order, so the result is the same for any thread count.
inline constexpr std::uint64_t kChunkSamples = 4096;
Sums run_chunks(std::uint64_t samples, std::size_t sums_size, std::uint64_t key,
                const std::function<void(Rng&, std::uint64_t count, Sums&)>& body);

}  // namespace mcref
