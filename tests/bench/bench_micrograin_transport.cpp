// Benchmarks of micrograin transport (issue #3), printed as a table:
// 1. ns/sample of the NDF sampler (unit space, LRPB23 Eq. 20) and of the vNDF
//    sampler (vNDF paper Listings 1–4, models/micrograin/vndf_sampler.h) at
//    theta_i = 20, 40, 60, 80 deg, 10^7 samples each, one thread, and the
//    vNDF/NDF ratio (paper, Table 2: 2.97–3.79 with triangle-cut phi).
// 2. Paths/s and rays/s of the BRDF walk (sim/estimators/micrograin_walk) on
//    2 threads (run_chunks, as the estimator), against bare rtcIntersect1 rays/s
//    on the same Embree scene (first-hit rays from the top, 2 threads). Field:
//    tau0 = 0.6, beta = 1, tile 200; Lambertian grains 0.8, base 0.5; theta_i = 40.
//    Walk and bare runs alternate, best of 5, to be robust to other load.
#include <embree3/rtcore.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "models/micrograin/ndf_sampling.h"
#include "models/micrograin/vndf_sampler.h"
#include "sim/core/rng.h"
#include "sim/estimators/estimator.h"
#include "sim/estimators/micrograin_walk.h"

using namespace mcref;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

template <class F>
double ns_per_sample(F&& sample, std::uint64_t n) {
  Rng rng(7);
  double sink = 0;
  const double t0 = now();
  for (std::uint64_t k = 0; k < n; ++k) {
    const Vec3 m = sample(rng.uniform(), rng.uniform());
    sink += m.z;
  }
  const double t = now() - t0;
  if (sink == 12345.678) std::printf("!");
  return 1e9 * t / static_cast<double>(n);
}

}  // namespace

int main() {
  const std::uint64_t n = 10000000;
  const double tau0 = 0.6;
  const double t_build = now();
  const micrograin::VndfSampler vndf;
  std::printf("vNDF sigma^-1 table (1024 x 1024) built in %.2f s\n\n", now() - t_build);
  std::printf("theta_i  NDF ns  vNDF ns  vNDF/NDF   (10^7 samples, 1 thread; tau0 = %.1f, unit space)\n", tau0);
  for (double ti : {20.0, 40.0, 60.0, 80.0}) {
    const Vec3 iu = spherical_direction(ti * kPi / 180, 0.3);
    const double a = ns_per_sample([&](double u1, double u2) { return micrograin::sample_unit_ndf(tau0, u1, u2); }, n);
    const double b = ns_per_sample([&](double u1, double u2) { return vndf.sample_unit(tau0, iu, u1, u2); }, n);
    std::printf("%5.0f    %6.1f  %7.1f  %6.2f\n", ti, a, b, b / a);
  }

  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
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
  double best_walk = 0, best_bare = 0, rays_per_path = 0;
  for (int rep = 0; rep < 5; ++rep) {
    double t0 = now();
    const Sums s = run_chunks(paths, layout.sums_size() + 1, 99 + rep, [&](Rng& rng, std::uint64_t count, Sums& acc) {
      BrdfAccumulator tally(layout, 0.0, acc);
      WalkCounters c;
      for (std::uint64_t k = 0; k < count; ++k) trace_brdf_path(f, mat, wi, 0, rng, tally, &c);
      acc[layout.sums_size()] += static_cast<double>(c.rays);
    });
    const double walk_time = now() - t0;
    const double rays = s[layout.sums_size()];
    rays_per_path = rays / paths;
    best_walk = std::max(best_walk, rays / walk_time);
    // Bare rtcIntersect1: the same number of rays, first hits from the top.
    const Vec3 d = -unit_direction(f, wi);
    const float tfar = static_cast<float>(-1.0 / d.z);
    RTCScene scene = f.embree_scene();
    t0 = now();
    const Sums b = run_chunks(static_cast<std::uint64_t>(rays), 1, 7 + rep, [&](Rng& rng, std::uint64_t count, Sums& acc) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      for (std::uint64_t k = 0; k < count; ++k) {
        const Vec3 o = uniform_top_origin(f, rng);
        RTCRayHit rh;
        rh.ray.org_x = static_cast<float>(o.x);
        rh.ray.org_y = static_cast<float>(o.y);
        rh.ray.org_z = static_cast<float>(o.z);
        rh.ray.dir_x = static_cast<float>(d.x);
        rh.ray.dir_y = static_cast<float>(d.y);
        rh.ray.dir_z = static_cast<float>(d.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = tfar;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.flags = 0;
        rh.ray.time = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        acc[0] += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      }
    });
    best_bare = std::max(best_bare, rays / (now() - t0));
    (void)b;
  }
  std::printf("\nBRDF walk, 2 threads: %.3g paths/s, %.3g rays/s (%.2f rays/path)\n", best_walk / rays_per_path,
              best_walk, rays_per_path);
  std::printf("bare rtcIntersect1, 2 threads: %.3g rays/s\n", best_bare);
  std::printf("walk overhead over bare rays: %.0f %% (target < 30 %%)\n", 100 * (best_bare / best_walk - 1));
  return 0;
}
