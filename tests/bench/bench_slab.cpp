// Benchmarks of the slab engine (issue #4), 2 threads unless stated.
//  slab/homogeneous : scattering events/s of the full engine (run_chunks, walk,
//                     BRDF tally) for one surface-like SGGX layer, alpha 0.5,
//                     albedo 0.9, T rho 5, theta_i = 30 deg, all orders.
//  slab/openvdb     : the same slab through OpenVDB delta tracking (constant grid).
//  slab/pair/<medium> : the homogeneous slab and a heterogeneous OpenVDB slab
//                     of the same optical thickness, albedo and SGGX parameters,
//                     run back to back in every iteration (order alternating;
//                     9 iterations of 2^18 paths each), same seeds:
//                       linear  : linear depth profile, multipliers 0.5 (top) to 1.5;
//                       lateral : density times 1 + 0.5 cos(2 pi x / tile) cos(2 pi y / tile),
//                                 16 x 16 voxels per tile (the tile's mean is the layer's);
//                     counters: ratio = median over the iterations of heterogeneous /
//                     homogeneous events per second of wall time, with its min and max;
//                     cpu_ratio the same per second of the process's CPU time (robust
//                     to other jobs on the machine). (Events per path: both.)
//  slab/pair/wave/<medium> : the same with the wave walk (sim/slab/wave_walk.h) on both sides.
//  slab/pair/walks/<medium> : the heterogeneous slab through the scalar walk, then
//                     through the wave walk (counters as above: wave / scalar;
//                     events/path_hom is the scalar walk's there).
//  slab/pair/cross/<medium> : the homogeneous slab through the scalar walk (the
//                     default walk), then the heterogeneous one through the wave walk
//                     (counters as above: het wave / hom scalar).
//  slab/pair/exact/linear : the linear profile in the scalar walk, delta-tracked
//                     (side 0), then flown exactly (sim/slab/depth_profile.h).
//  slab/flight/<medium> : free flights alone, 1 thread: 2^16 photons spread over
//                     the layer (uniform in the tile and in depth, isotropic
//                     directions) flown once each to their next collision or out,
//                     through the homogeneous slab and the slab/pair medium back to
//                     back (order alternating; 9 iterations), same seeds; counters:
//                     ns_hom, ns_het per flight and time_ratio = het / hom time,
//                     median with min and max over the iterations.
//  slab/floor       : a minimal homogeneous walk written here (one layer, exact
//                     exponential flights, the same SGGX vNDF sampler, no tally,
//                     no virtual calls, plain analog absorption by albedo): the floor.
//  slab/wave        : the data-parallel walk (sim/slab/wave_walk.h), the floor
//                     and the full scalar walk on the same medium, 1 thread each,
//                     back to back in every iteration (order rotating; 9 iterations),
//                     2^15 paths each; counters: wave = median over the iterations of
//                     wave / floor events per second of the thread's CPU time, with min
//                     and max; scalar the same for the full scalar walk (walk.h).
//  slab/wave2       : the same on two layers (surface-like SGGX alpha 0.5, T rho 2.5,
//                     over fibre-like SGGX alpha 0.5 along x, T rho 2.5; albedo 0.9),
//                     against a minimal two-layer walk written here (floor_stack_path).
//  slab/bsdf32      : paths/s over 32 incident directions stratified in cos theta_i
//                     (the paper's Sec. 5 grid in theta); the time of one 32 x 32-direction
//                     BSDF at 1e5 paths per direction is extrapolated as 1024 * 1e5 / (paths/s).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <time.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "models/core/warp.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/experiment/experiment.h"
#include "sim/micrograin/estimator.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/walk.h"
#include "sim/slab/wave_walk.h"

namespace {

using namespace mcref;

constexpr std::uint64_t kPaths = 1 << 16;
constexpr std::uint64_t kPairPaths = 1 << 18;  // slab/pair: ~70 ms per side, steadier ratios

Experiment slab(bool openvdb, const std::string& extra_geometry = "", const std::string& extra_layer = "") {
  std::string text = "[geometry]\nkind = \"slab\"\n";
  if (openvdb) text += "backend = \"openvdb\"\ndepth_voxels = 32\n";
  text += extra_geometry + "[[geometry.layer]]\n" + extra_layer + R"(phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
optical_thickness = 5.0
albedo = 0.9
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)";
  return parse_experiment(text, "bench.toml");
}

// Paths through the engine (the scalar walk, or the wave walk); returns scattering events.
std::uint64_t engine_paths(const volume::SlabMedium& medium, const std::vector<Vec3>& dirs, std::uint64_t paths,
                           std::uint64_t seed, bool wave = false) {
  BrdfLayout layout;
  layout.transmission = true;
  layout.folded = true;
  layout.order1_classes = {"volume", "substrate"};
  std::atomic<std::uint64_t> events{0};
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    run_chunks(paths, layout.sums_size(), stream_seed({seed, d}), [&](Rng& rng, std::uint64_t count, Sums& s) {
      BrdfAccumulator acc(layout, 0.0, s);
      volume::WalkSettings ws;
      if (wave) {
        events += volume::wave_walk(medium, ws, dirs[d], count, rng, acc);
        return;
      }
      auto flight = volume::make_flight(medium);
      std::uint64_t e = 0;
      for (std::uint64_t n = 0; n < count; ++n) e += volume::walk(medium, *flight, ws, dirs[d], rng, acc);
      events += e;
    });
  }
  return events;
}

void engine(benchmark::State& state, bool openvdb) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  const Experiment ex = slab(openvdb);
  const volume::SlabMedium medium(ex.slab);
  const std::vector<Vec3> dirs{spherical_direction(30 * kPi / 180, 0)};
  std::uint64_t events = 0, paths = 0, it = 0;
  for (auto _ : state) {
    events += engine_paths(medium, dirs, kPaths, ++it);
    paths += kPaths;
  }
  state.counters["events/s"] = benchmark::Counter(static_cast<double>(events), benchmark::Counter::kIsRate);
  state.counters["paths/s"] = benchmark::Counter(static_cast<double>(paths), benchmark::Counter::kIsRate);
  state.counters["events/path"] = static_cast<double>(events) / static_cast<double>(paths);
}

// The heterogeneous slabs of slab/pair (the same layer as slab(false));
// depth_profiles = false: the linear profile delta-tracked, not flown exactly.
std::unique_ptr<volume::SlabMedium> heterogeneous(const std::string& kind, bool depth_profiles = true) {
  if (kind == "linear") {
    const SlabGeometry g = slab(true, "", "profile = \"linear\"\nprofile_top = 0.5\nprofile_bottom = 1.5\n").slab;
    return std::make_unique<volume::SlabMedium>(g, std::make_unique<volume::DensityGrids>(g), 0, 0, depth_profiles);
  }
  const SlabGeometry g = slab(true, "lateral_voxels = 16\n").slab;
  auto grids = std::make_unique<volume::DensityGrids>(g);
  const int n = g.grid.lateral_voxels;
  for (const openvdb::FloatGrid::Ptr& grid : grids->grids())
    for (auto it = grid->beginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      it.setValue(*it * static_cast<float>(1 + 0.5 * std::cos(2 * kPi * c.x() / n) * std::cos(2 * kPi * c.y() / n)));
    }
  return std::make_unique<volume::SlabMedium>(g, std::move(grids));
}

// CPU time of the whole process (all threads), s.
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// name = median of v, name_min and name_max.
void report_spread(benchmark::State& state, const std::string& name, const std::vector<double>& v) {
  state.counters[name] = median(v);
  state.counters[name + "_min"] = *std::min_element(v.begin(), v.end());
  state.counters[name + "_max"] = *std::max_element(v.begin(), v.end());
}

// What slab/pair runs on each side: side 0 the homogeneous slab (or the
// heterogeneous one, delta-tracked if `tracked`), side 1 the heterogeneous
// slab; each through the wave walk or the scalar walk.
struct Sides {
  bool het0 = false, tracked0 = false, wave0 = false, wave1 = false;
};
constexpr Sides kScalar{}, kWave{false, false, true, true}, kWalks{true, false, false, true},
    kTracked{true, true, false, false}, kCross{false, false, false, true};

// Two runs back to back, the order alternating: side 0 and side 1 (Sides).
void pair(benchmark::State& state, std::string kind, Sides sides) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  const volume::SlabMedium homogeneous(slab(false).slab);
  const std::unique_ptr<volume::SlabMedium> het = heterogeneous(kind);
  const std::unique_ptr<volume::SlabMedium> het_tracked = sides.tracked0 ? heterogeneous(kind, false) : nullptr;
  const std::vector<Vec3> dirs{spherical_direction(30 * kPi / 180, 0)};
  using clock = std::chrono::steady_clock;
  double events[2] = {0, 0};
  std::vector<double> wall_ratios, cpu_ratios;  // side 1 / side 0 events per second
  std::uint64_t it = 0;
  for (auto _ : state) {
    ++it;
    double wall[2], cpu[2], e[2];
    for (int k = 0; k < 2; ++k) {
      const int which = (k + static_cast<int>(it)) % 2;  // side
      const volume::SlabMedium& medium = which ? *het : sides.tracked0 ? *het_tracked : sides.het0 ? *het : homogeneous;
      const bool side_wave = which ? sides.wave1 : sides.wave0;
      const auto t0 = clock::now();
      const double c0 = process_cpu_seconds();
      e[which] = static_cast<double>(engine_paths(medium, dirs, kPairPaths, it, side_wave));
      cpu[which] = process_cpu_seconds() - c0;
      wall[which] = std::chrono::duration<double>(clock::now() - t0).count();
    }
    for (int w = 0; w < 2; ++w) events[w] += e[w];
    wall_ratios.push_back(e[1] / wall[1] / (e[0] / wall[0]));
    cpu_ratios.push_back(e[1] / cpu[1] / (e[0] / cpu[0]));
  }
  const double paths = static_cast<double>(kPairPaths) * static_cast<double>(it);
  report_spread(state, "ratio", wall_ratios);
  report_spread(state, "cpu_ratio", cpu_ratios);
  state.counters["events/path_hom"] = events[0] / paths;
  state.counters["events/path_het"] = events[1] / paths;
}

// Free flights alone (no scattering, no tally), 1 thread: 2^16 photons spread
// uniformly over the tile and the layer's depth with isotropic directions, each
// flown once to its next collision or out of the slab, through the homogeneous
// and the heterogeneous medium back to back (order alternating), same seeds.
void flights(benchmark::State& state, std::string kind) {
  const volume::SlabMedium homogeneous(slab(false).slab);
  const std::unique_ptr<volume::SlabMedium> het = heterogeneous(kind);
  const std::unique_ptr<volume::FreeFlight> fly[2] = {volume::make_flight(homogeneous), volume::make_flight(*het)};
  std::vector<volume::Photon> start(1 << 16);
  Rng placement(7);
  for (volume::Photon& p : start) {
    p.x = placement.uniform();
    p.y = placement.uniform();
    p.depth = placement.uniform();  // the layer: thickness 1
    p.d = sample_uniform_sphere(placement);
  }
  std::vector<double> ns[2], ratios;
  double sink = 0;
  std::uint64_t it = 0;
  for (auto _ : state) {
    ++it;
    double t[2];
    for (int k = 0; k < 2; ++k) {
      const int which = (k + static_cast<int>(it)) % 2;  // 0: homogeneous, 1: heterogeneous
      Rng rng(stream_seed({it}));
      const auto t0 = std::chrono::steady_clock::now();
      for (volume::Photon p : start) {
        fly[which]->fly(p, rng);
        sink += p.depth;
      }
      t[which] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    for (int w = 0; w < 2; ++w) ns[w].push_back(1e9 * t[w] / static_cast<double>(start.size()));
    ratios.push_back(t[1] / t[0]);
  }
  benchmark::DoNotOptimize(sink);
  report_spread(state, "ns_hom", ns[0]);
  report_spread(state, "ns_het", ns[1]);
  report_spread(state, "time_ratio", ratios);
}

// The floor: one homogeneous layer, nothing but the physics.
std::uint64_t floor_path(const sggx::Sggx& s, double tau, double albedo, Vec3 d, Rng& rng) {
  double depth = 0;
  std::uint64_t events = 0;
  for (;;) {
    const double sigma = sggx::projected_area(s, d);
    const double t = -std::log1p(-rng.uniform()) / sigma;
    depth -= d.z * t;
    if (depth < 0 || depth > tau) return events;
    ++events;
    if (rng.uniform() >= albedo) return events;
    const Vec3 wi = -d;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 m = sggx::sample_visible_normal(s, wi, u1, u2);
    d = m * (2 * dot(wi, m)) - wi;
  }
}

// The floor on a stack: exact exponential flights carried across the faces,
// nothing but the physics.
struct FloorLayer {
  sggx::Sggx s;
  double top, bottom, density;
};
std::uint64_t floor_stack_path(const std::vector<FloorLayer>& l, double albedo, Vec3 d, Rng& rng) {
  double depth = 0;
  int k = 0;
  const int layers = static_cast<int>(l.size());
  std::uint64_t events = 0;
  for (;;) {
    double tau = -std::log1p(-rng.uniform());
    for (;;) {
      const double mu = l[k].density * sggx::projected_area(l[k].s, d), rate = -d.z;
      const double dist = ((rate > 0 ? l[k].bottom : l[k].top) - depth) / rate;
      if (tau < mu * dist) {
        depth += rate * (tau / mu);
        break;
      }
      tau -= mu * dist;
      depth = rate > 0 ? l[k].bottom : l[k].top;
      k += rate > 0 ? 1 : -1;
      if (k < 0 || k == layers) return events;
    }
    ++events;
    if (rng.uniform() >= albedo) return events;
    const Vec3 wi = -d;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 m = sggx::sample_visible_normal(l[k].s, wi, u1, u2);
    d = m * (2 * dot(wi, m)) - wi;
  }
}

void floor_walk(benchmark::State& state) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  const sggx::Sggx s = sggx::surface_like(0.5, {0, 0, 1});
  const Vec3 d0 = -spherical_direction(30 * kPi / 180, 0);
  std::uint64_t events = 0, paths = 0, it = 0;
  for (auto _ : state) {
    const std::uint64_t chunks = kPaths / kChunkSamples;
    std::vector<std::uint64_t> e(chunks, 0);
    ++it;
    tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
      Rng rng(stream_seed({it, c}));
      for (std::uint64_t n = 0; n < kChunkSamples; ++n) e[c] += floor_path(s, 5.0, 0.9, d0, rng);
    });
    for (std::uint64_t x : e) events += x;
    paths += kPaths;
  }
  state.counters["events/s"] = benchmark::Counter(static_cast<double>(events), benchmark::Counter::kIsRate);
  state.counters["paths/s"] = benchmark::Counter(static_cast<double>(paths), benchmark::Counter::kIsRate);
  state.counters["events/path"] = static_cast<double>(events) / static_cast<double>(paths);
}

// CPU time of the calling thread, s.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The floor, the full scalar walk and the wave walk, 1 thread, on the calling thread;
// one layer, or two (slab/wave2).
void wave(benchmark::State& state, int layers) {
  const Experiment ex = layers == 1 ? slab(false) : parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 0.5
optical_thickness = 2.5
albedo = 0.9
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.5
orientation = [1, 0, 0]
thickness = 0.5
optical_thickness = 2.5
albedo = 0.9
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)", "bench.toml");
  const volume::SlabMedium medium(ex.slab);
  const sggx::Sggx s = sggx::surface_like(0.5, {0, 0, 1});
  const std::vector<FloorLayer> stack{{s, 0.0, 0.5, 5.0}, {sggx::fiber_like(0.5, {1, 0, 0}), 0.5, 1.0, 5.0}};
  const Vec3 wi = spherical_direction(30 * kPi / 180, 0);
  BrdfLayout layout;
  layout.transmission = true;
  layout.order1_classes = {"volume", "substrate"};
  const volume::WalkSettings ws;
  const std::uint64_t chunks = (kPaths / 2) / kChunkSamples;
  // Events of one run of `which` (0 floor, 1 scalar walk, 2 wave walk).
  const auto run = [&](int which, std::uint64_t it) {
    std::uint64_t events = 0;
    Sums sums(layout.sums_size(), 0.0);
    BrdfAccumulator acc(layout, 0.0, sums);
    const auto flight = volume::make_flight(medium);
    for (std::uint64_t c = 0; c < chunks; ++c) {
      Rng rng(stream_seed({it, c}));
      if (which == 2) {
        events += volume::wave_walk(medium, ws, wi, kChunkSamples, rng, acc);
        continue;
      }
      for (std::uint64_t n = 0; n < kChunkSamples; ++n)
        events += which == 0   ? (layers == 1 ? floor_path(s, 5.0, 0.9, -wi, rng) : floor_stack_path(stack, 0.9, -wi, rng))
                  : static_cast<std::uint64_t>(volume::walk(medium, *flight, ws, wi, rng, acc));
    }
    benchmark::DoNotOptimize(sums.data());
    return static_cast<double>(events);
  };
  std::vector<double> wave_ratio, scalar_ratio;
  double events[3] = {0, 0, 0};
  std::uint64_t it = 0;
  for (auto _ : state) {
    ++it;
    double rate[3];
    for (int k = 0; k < 3; ++k) {
      const int which = static_cast<int>((k + it) % 3);
      const double t0 = thread_cpu_seconds();
      const double e = run(which, it);
      rate[which] = e / (thread_cpu_seconds() - t0);
      events[which] += e;
    }
    wave_ratio.push_back(rate[2] / rate[0]);
    scalar_ratio.push_back(rate[1] / rate[0]);
  }
  const double paths = static_cast<double>(chunks * kChunkSamples) * static_cast<double>(it);
  report_spread(state, "wave", wave_ratio);
  report_spread(state, "scalar", scalar_ratio);
  for (int w = 0; w < 3; ++w) state.counters[std::string("events/path_") + "fsw"[w]] = events[w] / paths;
}

void bsdf32(benchmark::State& state) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  const Experiment ex = slab(false);
  const volume::SlabMedium medium(ex.slab);
  std::vector<Vec3> dirs;
  for (int k = 0; k < 32; ++k) dirs.push_back(spherical_direction(std::acos(1 - (k + 0.5) / 32), 0.3 * k));
  const std::uint64_t per_dir = 1 << 13;
  std::uint64_t paths = 0, it = 0;
  for (auto _ : state) {
    engine_paths(medium, dirs, per_dir, ++it);
    paths += per_dir * dirs.size();
  }
  state.counters["paths/s"] = benchmark::Counter(static_cast<double>(paths), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(engine, homogeneous, false)->Name("slab/homogeneous")->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(engine, openvdb, true)->Name("slab/openvdb")->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(pair, linear, "linear", kScalar)->Name("slab/pair/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, lateral, "lateral", kScalar)->Name("slab/pair/lateral")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, wave_linear, "linear", kWave)->Name("slab/pair/wave/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, wave_lateral, "lateral", kWave)->Name("slab/pair/wave/lateral")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, walks_linear, "linear", kWalks)->Name("slab/pair/walks/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, walks_lateral, "lateral", kWalks)->Name("slab/pair/walks/lateral")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, cross_linear, "linear", kCross)->Name("slab/pair/cross/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, cross_lateral, "lateral", kCross)->Name("slab/pair/cross/lateral")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(pair, exact_linear, "linear", kTracked)->Name("slab/pair/exact/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(flights, linear, "linear")->Name("slab/flight/linear")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(flights, lateral, "lateral")->Name("slab/flight/lateral")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(floor_walk)->Name("slab/floor")->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK_CAPTURE(wave, one, 1)->Name("slab/wave")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(wave, two, 2)->Name("slab/wave2")->Iterations(9)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(bsdf32)->Name("slab/bsdf32")->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

BENCHMARK_MAIN();
