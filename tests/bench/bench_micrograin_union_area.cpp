// Cost of the union form of the two-direction masking (issue #15):
//   area_<form>/<theta>: cap_shadow_union_area, |K_i(h) U K_o(h)| - pi (1 - h^2),
//     per call (items), over 32 configurations: theta_i = theta_o = theta, relative
//     azimuth 0.001, 0.3, 1.5, 3 rad, h = (k + 1/2)/8 sin theta (k = 0..7, all with a
//     shadow beyond the disc). <form> = closed (the model) or adaptive (the former
//     adaptive integral, tests/models/micrograin_union_area_reference.h, with the
//     model's old settings: 48-point crossing grid, tolerance 1e-10).
//   node/<theta_o>: one union G_dist BRDF node, gdist_grain_single_scattering with
//     TwoWay::Union, Lambertian grains (kd 0.8), tau0 = 0.4, beta = 1, theta_i = 80 deg,
//     relative azimuth 1 rad.
// Run with --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "models/micrograin/micrograin_bsdf.h"
#include "models/micrograin/two_way_masking.h"
#include "tests/models/micrograin_union_area_reference.h"

namespace {

using namespace mcref;
using namespace mcref::micrograin;

constexpr double kDeg = kPi / 180;

struct Config {
  Vec3 i, o;
  double h;
};

std::vector<Config> configs(double theta_deg) {
  std::vector<Config> c;
  const double t = theta_deg * kDeg;
  for (double dphi : {0.001, 0.3, 1.5, 3.0})
    for (int k = 0; k < 8; ++k)
      c.push_back({spherical_direction(t, 0.2), spherical_direction(t, 0.2 + dphi), (k + 0.5) / 8 * std::sin(t)});
  return c;
}

template <bool kClosed>
void area(benchmark::State& state, double theta_deg) {
  const std::vector<Config> c = configs(theta_deg);
  for (auto _ : state)
    for (const Config& x : c) {
      const double a = kClosed ? cap_shadow_union_area(x.i, x.o, x.h) : test::union_area_adaptive(x.i, x.o, x.h);
      benchmark::DoNotOptimize(a);
    }
  state.SetItemsProcessed(state.iterations() * c.size());
}
void area_closed(benchmark::State& state, double theta_deg) { area<true>(state, theta_deg); }
void area_adaptive(benchmark::State& state, double theta_deg) { area<false>(state, theta_deg); }

void node(benchmark::State& state, double theta_o_deg) {
  const GrainField f = isotropic_field(0.4, 1.0);
  const MicroSurface grain{};  // Lambertian, kd 0.8
  const Vec3 i = spherical_direction(80 * kDeg, 0.0), o = spherical_direction(theta_o_deg * kDeg, 1.0);
  for (auto _ : state) benchmark::DoNotOptimize(gdist_grain_single_scattering(f, grain, i, o, TwoWay::Union));
}

BENCHMARK_CAPTURE(area_closed, 45, 45.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(area_adaptive, 45, 45.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(area_closed, 89.99, 89.99)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(area_adaptive, 89.99, 89.99)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(node, 45, 45.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(node, 89.99, 89.99)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
