// Benchmarks of micrograin transport (issue #3), printed as a table.
// Usage: bench_micrograin_transport [threads (default 2)]
// (The normal samplers' costs, once item 1 here, are measured by
// bench_micrograin_samplers.)
// Paths/s and rays/s of the BRDF walk (sim/micrograin/micrograin_walk) on
//    2 threads (run_chunks, as the estimator; optional argument: threads),
//    against the walk's own rtcIntersect1 calls replayed bare (same rays, same
//    self-hit filter) and first-hit rays from the top on the same scene. Field:
//    tau0 = 0.6, beta = 1, tile 200; Lambertian grains 0.8, base 0.5; theta_i = 40.
//    Walk and bare runs alternate, 9 times: the overhead is taken from the best
//    time of each (robust to other load), and the spread of the 9 paired
//    walk/replay ratios is printed beside it.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "models/core/rng.h"
#include "sim/micrograin/estimator.h"
#include "sim/micrograin/micrograin_walk.h"
#include "sim/micrograin/ray_log.h"

using namespace mcref;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

int main(int argc, char** argv) {
  const double tau0 = 0.6;
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  MicrograinGeometry g;
  g.tau0 = tau0;
  g.beta_x = g.beta_y = 1.0;
  g.tile = 200;
  const MicrograinField f(g, 3);
  MicrograinMaterials mat;
  mat.configured = true;
  mat.grain.type = MicroBrdf::Type::Lambertian;
  mat.grain.albedo = Rgb(0.8);
  mat.base.type = MicroBrdf::Type::Lambertian;
  mat.base.albedo = Rgb(0.5);
  BrdfLayout layout;
  layout.theta_o_bins = 16;
  layout.phi_bins = 18;
  layout.order1_classes = {"grain", "base"};
  const Vec3 wi = incident_direction(40 * kPi / 180, 0);
  const std::uint64_t paths = 1 << 20;
  auto walk = [&](std::uint64_t key) {
    return run_chunks(paths, layout.sums_size() + 1, key, [&](Rng& rng, std::uint64_t count, Sums& acc) {
      BrdfAccumulator tally(layout, 0.0, acc);
      WalkCounters c;
      for (std::uint64_t k = 0; k < count; ++k) trace_brdf_path(f, mat, wi, 0, rng, tally, &c);
      acc[layout.sums_size()] += static_cast<double>(c.rays);
    });
  };

  // The rays the walk gives Embree, recorded on one thread (untimed) from
  // another realisation of the same walk (same distribution of rays).
  std::vector<LoggedRay> rays;
  rays.reserve(3 * paths);
  t_ray_log = &rays;
  {
    Rng rng(12345);
    Sums acc(layout.sums_size());
    BrdfAccumulator tally(layout, 0.0, acc);
    for (std::uint64_t k = 0; k < paths; ++k) trace_brdf_path(f, mat, wi, 0, rng, tally);
  }
  t_ray_log = nullptr;
  auto trace = [&](const LoggedRay& r) {
    RTCRayHit rh;
    f.embree_intersect(r, rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  };
  auto replay = [&](const std::vector<LoggedRay>& v) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, v.size(), 4096), std::size_t{0},
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t hits) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) hits += trace(v[k]);
          return hits;
        },
        std::plus<>());
  };
  // First-hit rays from the top, as many as the walk's Embree calls.
  std::vector<LoggedRay> top(rays.size());
  {
    Rng rng(7);
    const Vec3 d = -unit_direction(f, wi);
    for (LoggedRay& r : top) {
      const Vec3 o = uniform_top_origin(f, rng);
      r = {{float(o.x), float(o.y), float(o.z)}, {float(d.x), float(d.y), float(d.z)}, 0.0f, float(-1.0 / d.z),
           o, MicrograinField::kNoGrain};
    }
  }

  // Walk, replay and first-hit runs alternate; best of 9 each, and the ratio
  // of each walk to the replay right after it.
  double t_walk = 1e30, t_replay = 1e30, t_top = 1e30, unit_rays = 0;
  std::vector<double> paired;
  for (int rep = 0; rep < 9; ++rep) {
    double t0 = now();
    const Sums s = walk(99 + rep);
    const double tw = now() - t0;
    t_walk = std::min(t_walk, tw);
    unit_rays = s[layout.sums_size()];
    t0 = now();
    replay(rays);
    const double tr = now() - t0;
    t_replay = std::min(t_replay, tr);
    paired.push_back(tw / tr - 1);
    t0 = now();
    replay(top);
    t_top = std::min(t_top, now() - t0);
  }
  const double calls = static_cast<double>(rays.size());
  std::printf("\nBRDF walk, %d threads, %llu paths: %.3g paths/s, %.3g rays/s (%.2f rays/path, %.2f rtcIntersect1/path)\n",
              threads, static_cast<unsigned long long>(paths), paths / t_walk, unit_rays / t_walk, unit_rays / paths,
              calls / paths);
  std::printf("the same rtcIntersect1 calls replayed bare, %d threads: %.3g calls/s\n", threads, calls / t_replay);
  std::printf("first-hit rays from the top, bare, %d threads: %.3g rays/s\n", threads, calls / t_top);
  std::printf("walk overhead over tracing its own rays: %.0f %% (target < 30 %%)\n", 100 * (t_walk / t_replay - 1));
  std::sort(paired.begin(), paired.end());
  std::printf("  the 9 paired runs: median %.0f %%, range %.0f-%.0f %%\n", 100 * paired[paired.size() / 2],
              100 * paired.front(), 100 * paired.back());
  std::printf("walk time / first-hit time for as many rays: %.2f\n", t_walk / t_top);
  return 0;
}
