// sim/parallel/run_chunks.h: the chunked runner every estimator samples with.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "sim/parallel/run_chunks.h"

using namespace mcref;

// run_chunks adds the chunks in chunk order whatever the thread count and the
// order in which they finish: bit-identical to adding them one by one on this
// thread. Chunk 0 (known by its first uniform) is slow (50 ms), so with 2
// threads the others finish first, and it adds 2^53 where the others add 1:
// in chunk order every 1 is rounded away (ties to even), in any other order
// some are kept.
TEST(RunChunks, AddsChunksInOrderWhateverTheThreadCount) {
  const std::uint64_t samples = 40 * kChunkSamples + 123, key = 77;
  const double first_of_chunk0 = Rng(stream_seed({key, 0})).uniform();
  auto body = [&](Rng& rng, std::uint64_t count, Sums& acc) {
    const bool chunk0 = rng.uniform() == first_of_chunk0;
    if (chunk0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    acc[0] += chunk0 ? 0x1p53 : 1.0;
    acc[1] += static_cast<double>(count);
  };
  Sums reference(2, 0.0);
  for (std::uint64_t c = 0; c * kChunkSamples < samples; ++c) {
    Sums acc(2, 0.0);
    Rng rng(stream_seed({key, c}));
    body(rng, std::min(kChunkSamples, samples - c * kChunkSamples), acc);
    for (int i = 0; i < 2; ++i) reference[i] += acc[i];
  }
  EXPECT_EQ(reference[0], 0x1p53);
  EXPECT_EQ(reference[1], static_cast<double>(samples));
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const Sums s = run_chunks(samples, 2, key, body);
    EXPECT_EQ(s[0], reference[0]) << threads << " threads";
    EXPECT_EQ(s[1], reference[1]) << threads << " threads";
  }
}
