// Cost of the G_dist diffuse geometry with Fresnel grains (the numeric ring):
//   <rule>/<theta_i>: gdist_diffuse_geometry per call (items), union masking,
//   tau0 = 0.4, beta = 1, ior 1.5 (the brdf_dspec cases), over 30 directions
//   o: theta_o = 5, 25, 45, 65, 80, 88 deg x relative azimuth 0, 1, 2, 3, pi rad.
//   <rule> = current (models/micrograin/micrograin_bsdf.cpp: diffuse_ring.h and
//   the checked polar rule) or former (tests/models/micrograin_gdist_former.h).
// Run with --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true.
#include <benchmark/benchmark.h>

#include <vector>

#include "models/micrograin/micrograin_bsdf.h"
#include "tests/models/micrograin_gdist_former.h"

namespace {

using namespace mcref;
using namespace mcref::micrograin;

constexpr double kDeg = kPi / 180;

template <bool kCurrent>
void rule(benchmark::State& state, double theta_i_deg) {
  const GrainField f = isotropic_field(0.4, 1.0);
  const Vec3 i = spherical_direction(theta_i_deg * kDeg, 0.0);
  std::vector<Vec3> os;
  for (double t : {5.0, 25.0, 45.0, 65.0, 80.0, 88.0})
    for (double phi : {0.0, 1.0, 2.0, 3.0, kPi}) os.push_back(spherical_direction(t * kDeg, phi));
  for (auto _ : state)
    for (const Vec3& o : os)
      benchmark::DoNotOptimize(kCurrent ? gdist_diffuse_geometry(f, i, o, 1.5, TwoWay::Union)
                                        : test::former_diffuse_geometry(f, i, o, 1.5, TwoWay::Union));
  state.SetItemsProcessed(state.iterations() * os.size());
}
void current(benchmark::State& state, double theta_i_deg) { rule<true>(state, theta_i_deg); }
void former(benchmark::State& state, double theta_i_deg) { rule<false>(state, theta_i_deg); }

}  // namespace

BENCHMARK_CAPTURE(current, 30, 30.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(former, 30, 30.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(current, 80, 80.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(former, 80, 80.0)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
