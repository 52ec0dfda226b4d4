// The C++ side of the Python speed check (tests/bench/python_model_speed.py):
// a plain loop evaluating a model over 10^6 points into a preallocated array,
// the same functions and inputs as the Python call
//   mcref.micrograin.<model>(0.5, 0.8, theta),  theta = linspace(0, 1.5, 10^6).
#include <benchmark/benchmark.h>

#include <vector>

#include "models/micrograin/ndf.h"
#include "models/micrograin/visible_filling_factor.h"

namespace {

constexpr int kPoints = 1000000;

std::vector<double> thetas() {
  std::vector<double> t(kPoints);
  for (int i = 0; i < kPoints; ++i) t[i] = 1.5 * i / (kPoints - 1);
  return t;
}

template <class F>
void loop(benchmark::State& state, F f) {
  const std::vector<double> theta = thetas();
  std::vector<double> out(kPoints);
  for (auto _ : state) {
    for (int i = 0; i < kPoints; ++i) out[i] = f(0.5, 0.8, theta[i]);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
}

void BM_tau_plus_eq22(benchmark::State& s) { loop(s, [](double a, double b, double t) { return mcref::micrograin::tau_plus(a, b, t); }); }
void BM_ndf_eq17(benchmark::State& s) { loop(s, [](double a, double b, double t) { return mcref::micrograin::ndf(a, b, t); }); }

}  // namespace

BENCHMARK(BM_tau_plus_eq22)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ndf_eq17)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
