#pragma once
// Counter-based seeding + a small fast generator.
// Every chunk of work owns an Rng seeded by stream_seed(run seed, realization,
// measure, direction, chunk), so results do not depend on thread scheduling.
#include <cstdint>
#include <initializer_list>

namespace mcref {

// SplitMix64 finaliser: a bijective 64-bit mix.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Hash of a tuple of counters; order matters.
inline std::uint64_t stream_seed(std::initializer_list<std::uint64_t> keys) {
  std::uint64_t h = 0x6a09e667f3bcc909ULL;
  for (std::uint64_t k : keys) h = mix64(h ^ mix64(k));
  return h;
}

// One step of xoshiro256** (Blackman & Vigna) on the state s0..s3: the output.
// (Also stepped on arrays of states by the data-parallel slab walk.)
inline std::uint64_t xoshiro256ss_next(std::uint64_t& s0, std::uint64_t& s1, std::uint64_t& s2, std::uint64_t& s3) {
  const auto rotl = [](std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); };
  const std::uint64_t result = rotl((s1 << 2) + s1, 7) * 9;  // (s1 * 5 as shift and add: AVX2 has no 64-bit multiply)
  const std::uint64_t t = s1 << 17;
  s2 ^= s0; s3 ^= s1; s1 ^= s2; s0 ^= s3;
  s2 ^= t; s3 = rotl(s3, 45);
  return result;
}

// xoshiro256**, state filled by SplitMix64 from the seed.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    for (int i = 0; i < 4; ++i) s_[i] = mix64(seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(i));
  }
  std::uint64_t next_u64() { return xoshiro256ss_next(s_[0], s_[1], s_[2], s_[3]); }
  // Uniform double in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  // Poisson variate of mean `mean` by counting unit-rate exponential arrivals
  // (exact; O(mean) draws, fine for the grain counts we need).
  std::uint64_t poisson(double mean);
  // Uniform integer in [0, n).
  std::uint64_t below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<unsigned __int128>(next_u64()) * n) >> 64);
  }

 private:
  std::uint64_t s_[4];
};

}  // namespace mcref

#include <cmath>
inline std::uint64_t mcref::Rng::poisson(double mean) {
  std::uint64_t n = 0;
  double t = -std::log1p(-uniform());
  while (t < mean) { ++n; t -= std::log1p(-uniform()); }
  return n;
}
