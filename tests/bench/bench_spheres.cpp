// Benchmarks of Lambertian-sphere volumes (single thread each):
//   packing_walk/<f>   : paths/s of the explicit packing walk (Poisson, c = 0.8,
//                        normal incidence, depth for T < 1e-4, tile 100)
//   trace/<f>          : SphereField::trace on random rays from random points
//                        of the slab (periodic wrapping, layers, double roots)
//   bare/<f>           : bare rtcIntersect1 on the same Embree scene and rays
//                        (float, no wrapping: the ray stops at the tile side)
//   volumetric_walk    : paths/s of the homogeneous half-space walk, c = 0.8
//   build_1e6          : placement + Embree build of ~10^6 Poisson spheres
//                        (f = 0.07), with our arrays' size and the resident
//                        memory increase.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <chrono>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "models/core/rng.h"
#include "models/core/warp.h"
#include "sim/spheres/sphere_field.h"
#include "sim/spheres/sphere_packing.h"
#include "sim/spheres/walks.h"

namespace {

using namespace mcref;

SpherePacking packing(double f) {
  SpherePacking p;
  p.placement = SpherePlacement::poisson;
  p.volume_fraction = f;
  p.albedo = Rgb(0.8);
  p.tile = 100;
  return p;
}

const SphereField& field_for(double f) {
  static std::map<double, std::unique_ptr<SphereField>> cache;
  auto& slot = cache[f];
  if (!slot) {
    Rng rng(11);
    slot = std::make_unique<SphereField>(place_poisson(packing(f), rng), packing(f).tile);
  }
  return *slot;
}

void BM_PackingWalk(benchmark::State& state) {
  const double f = state.range(0) / 1000.0;
  const SphereField& field = field_for(f);
  BrdfLayout l;
  l.order1_classes = {"sphere"};
  std::vector<double> sums(l.sums_size(), 0.0);
  BrdfAccumulator acc(l, 0.0, sums);
  WalkSettings s;
  s.albedo = Rgb(0.8);
  Rng rng(1);
  Rgb tr;
  for (auto _ : state) packing_path(field, s, {0, 0, 1}, rng, acc, tr);
  state.counters["paths/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["spheres"] = static_cast<double>(field.sphere_count());
}

// Random rays from random points of the slab (some start inside spheres: the
// same for both variants, it only changes which hits are reported).
struct RandomRay {
  Vec3 o, d;
};
RandomRay random_ray(const SphereField& field, Rng& rng) {
  return {{rng.uniform() * field.tile(), rng.uniform() * field.tile(),
           field.bottom() + rng.uniform() * (field.top() - field.bottom())},
          sample_uniform_sphere(rng.uniform(), rng.uniform())};
}

void BM_Trace(benchmark::State& state) {
  const SphereField& field = field_for(state.range(0) / 1000.0);
  Rng rng(2);
  for (auto _ : state) {
    const RandomRay r = random_ray(field, rng);
    benchmark::DoNotOptimize(field.trace(r.o, r.d));
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_Bare(benchmark::State& state) {
  const SphereField& field = field_for(state.range(0) / 1000.0);
  Rng rng(2);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (auto _ : state) {
    const RandomRay r = random_ray(field, rng);
    const int k = field.layer_of(r.o.z);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(r.o.x);
    rh.ray.org_y = static_cast<float>(r.o.y);
    rh.ray.org_z = static_cast<float>(r.o.z - field.layer_origin(k));
    rh.ray.dir_x = static_cast<float>(r.d.x);
    rh.ray.dir_y = static_cast<float>(r.d.y);
    rh.ray.dir_z = static_cast<float>(r.d.z);
    rh.ray.tnear = 0;
    rh.ray.tfar = 1e30f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(field.layer_scene(k), &context, &rh);
    benchmark::DoNotOptimize(rh.hit.primID);
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_VolumetricWalk(benchmark::State& state) {
  BrdfLayout l;
  l.order1_classes = {"sphere"};
  std::vector<double> sums(l.sums_size(), 0.0);
  BrdfAccumulator acc(l, 0.0, sums);
  WalkSettings s;
  s.albedo = Rgb(state.range(0) / 1000.0);
  s.depth_mfp = transmission_depth_mfp(s.albedo.max(), 1e-4);
  Rng rng(3);
  Rgb tr;
  for (auto _ : state) volumetric_path(s, {0, 0, 1}, rng, acc, tr);
  state.counters["paths/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

long resident_kb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

void BM_Build1e6(benchmark::State& state) {
  SpherePacking p = packing(0.07);
  p.tile = 100;
  p.tile = std::sqrt(1e6 / (p.number_density() * p.depth()));  // expected count 10^6
  for (auto _ : state) {
    const long before = resident_kb();
    const auto t0 = std::chrono::steady_clock::now();
    Rng rng(4);
    std::vector<Vec3> c = place_poisson(p, rng);
    const auto t1 = std::chrono::steady_clock::now();
    SphereField field(std::move(c), p.tile);
    const auto t2 = std::chrono::steady_clock::now();
    state.counters["spheres"] = static_cast<double>(field.sphere_count());
    state.counters["primitives"] = static_cast<double>(field.primitive_count());
    state.counters["place_s"] = std::chrono::duration<double>(t1 - t0).count();
    state.counters["build_s"] = std::chrono::duration<double>(t2 - t1).count();
    state.counters["arrays_MB"] = field.array_bytes() / 1e6;
    state.counters["rss_increase_MB"] = (resident_kb() - before) / 1e3;
  }
}

}  // namespace

BENCHMARK(BM_PackingWalk)->Arg(5)->Arg(70)->Arg(300)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Trace)->Arg(5)->Arg(70)->Arg(300)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Bare)->Arg(5)->Arg(70)->Arg(300)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_VolumetricWalk)->Arg(800)->Arg(990)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Build1e6)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
