// The cost of the micrograin normal samplers, in the unit space (issue #15
// part 6; the vNDF paper's Table 2): the NDF sampler (LRPB23 Eq. 20, sign
// corrected; models/micrograin/ndf_sampling.h) and the vNDF sampler
// (Listings 1–4; models/micrograin/vndf_sampler.h), tau0 = 0.6, theta_i' =
// 20, 40, 60, 80 deg, one thread.
//
// pair/theta_i:T : in every iteration one batch of 2^16 NDF samples and one
// of 2^16 vNDF samples, back to back, the order alternating between
// iterations; counters ndf_ns and vndf_ns (per sample, the thread's CPU
// time: robust to load from other processes) and ratio = vNDF time / NDF
// time. Run with --benchmark_repetitions=N for the spread over repetitions.
// tau0 and i are read through volatiles at every sample, so that the compiler
// cannot hoist their part of the work out of the loop: the cost of a call
// with new arguments, as in a path tracer. The uniforms come from the same
// Rng in both samplers (its cost, ~2 ns per uniform, is in both times).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include "models/core/rng.h"
#include "tests/bench/thread_cpu_time.h"
#include "models/core/vec.h"
#include "models/micrograin/ndf_sampling.h"
#include "models/micrograin/vndf_sampler.h"

namespace {

using namespace mcref;

constexpr std::uint64_t kBatch = 1 << 16;
constexpr double kTau0 = 0.6;

const micrograin::VndfSampler& vndf() {
  static const micrograin::VndfSampler s;
  return s;
}

// Seconds for one batch of the sampler `vndf_on` (false: NDF). Every component
// of every normal enters the sum: with m.z alone, the compiler drops the
// work for phi (m.z = cos theta), and only the calls it cannot remove survive.
double batch(bool vndf_on, Vec3 iu, std::uint64_t seed, double& sink) {
  volatile double v_tau0 = kTau0, v_ix = iu.x, v_iy = iu.y, v_iz = iu.z;
  Rng rng(seed);
  double s = 0;
  const double t0 = bench::thread_cpu_seconds();
  if (vndf_on) {
    const micrograin::VndfSampler& sampler = vndf();
    for (std::uint64_t k = 0; k < kBatch; ++k) {
      const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
      const Vec3 m = sampler.sample_unit(v_tau0, {v_ix, v_iy, v_iz}, u1, u2, u3);
      s += m.x + m.y + m.z;
    }
  } else {
    for (std::uint64_t k = 0; k < kBatch; ++k) {
      const double u1 = rng.uniform(), u2 = rng.uniform();
      rng.uniform();  // the vNDF sampler's third uniform: the same RNG cost in both loops
      const Vec3 m = micrograin::sample_unit_ndf(v_tau0, u1, u2);
      s += m.x + m.y + m.z;
    }
  }
  const double t = bench::thread_cpu_seconds() - t0;
  sink += s;
  return t;
}

void bm_pair(benchmark::State& state, double theta_i_deg) {
  const Vec3 iu = spherical_direction(theta_i_deg * kPi / 180, 0.3);
  vndf();  // the sigma^-1 table, built outside the timed loop
  double t_ndf = 0, t_vndf = 0, sink = 0;
  std::uint64_t seed = 1;
  bool vndf_first = false;
  for (auto _ : state) {
    for (int k = 0; k < 2; ++k) {
      const bool v = (k == 0) == vndf_first;
      (v ? t_vndf : t_ndf) += batch(v, iu, seed++, sink);
    }
    vndf_first = !vndf_first;
  }
  benchmark::DoNotOptimize(sink);
  const double n = static_cast<double>(kBatch) * static_cast<double>(state.iterations());
  state.counters["ndf_ns"] = 1e9 * t_ndf / n;
  state.counters["vndf_ns"] = 1e9 * t_vndf / n;
  state.counters["ratio"] = t_vndf / t_ndf;
}

}  // namespace

int main(int argc, char** argv) {
  for (double t : {20.0, 40.0, 60.0, 80.0})
    benchmark::RegisterBenchmark(("pair/theta_i:" + std::to_string(static_cast<int>(t))).c_str(), bm_pair, t)
        ->MinTime(1.0)->UseRealTime()->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
