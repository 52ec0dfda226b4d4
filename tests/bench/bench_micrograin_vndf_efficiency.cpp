// The vNDF paper's Fig. 6 claim in numbers (issue #15 part 6): vNDF sampling
// is more efficient than NDF sampling except near normal incidence.
//
// Estimated: the radiance reflected toward i by the G_dist BSDF's grain term
// (vNDF paper Eq. 1; gold conductor grains, eta 0.18299, kappa 3.4242, the
// red channel of the paper's Figs. 7 and 9; models/micrograin/micrograin_bsdf.h,
// gdist_grain_specular, masking G_dist(i, h) G_dist(o, h)) under fixed lighting:
//   sky: uniform radiance 1 over the upper hemisphere (the estimate is the
//        grain term's directional albedo);
//   sun: a disc of half-angle 5 deg around theta = 30 deg, on the mirror side
//        of i (azimuth pi), radiance 1 / its solid angle (a "directional" light
//        that a sampled direction can hit).
// Both samplers feed the same one-sample estimator: m from the sampler, o the
// mirror of i about m, weight f(i, o) cos theta_o L(o) / pdf(o) with
// pdf(o) = pdf(m) / (4 i.m), f and pdf(m) evaluated by the models (NDF:
// D(m) cos theta_m, ndf_pdf; vNDF: visible_ndf, Eq. 6); weight 0 when i.m <= 0
// or o is below the horizon. The base term is left out: it is sampled the same
// way by both (as in the paper, Sec. 5).
//
// pair/<tau0>/<beta>/<light>/theta_i:T : in every iteration one batch of 2^14
// samples with each sampler, back to back, the order alternating. Counters:
// per-sample variance and mean of each estimator, ns per sample (sampling
// plus evaluation; the thread's CPU time) and the efficiency ratio
//   eff_ratio = (var_ndf t_ndf) / (var_vndf t_vndf)   (> 1: vNDF more efficient),
// with var_ratio = var_ndf / var_vndf and time_ratio = t_vndf / t_ndf beside
// it. Both samplers draw the same number of samples (the same uniforms), and
// every repetition new ones. Run with
// --benchmark_repetitions=N (N >= 5) for the spread; tests/bench/vndf_efficiency.py
// turns the JSON output into the table and the plot.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "models/core/rng.h"
#include "tests/bench/thread_cpu_time.h"
#include "models/core/vec.h"
#include "models/micrograin/micrograin_bsdf.h"
#include "models/micrograin/ndf_sampling.h"
#include "models/micrograin/visible_ndf.h"
#include "models/micrograin/vndf_sampler.h"

namespace {

using namespace mcref;
namespace mg = mcref::micrograin;

constexpr std::uint64_t kBatch = 1 << 14;
constexpr double kDeg = kPi / 180;
constexpr double kSunHalfAngle = 5 * kDeg, kSunTheta = 30 * kDeg;

const mg::VndfSampler& vndf() {
  static const mg::VndfSampler s;
  return s;
}

struct Lighting {
  bool sun;
  Vec3 dir;            // the sun's centre
  double cos_radius;   // cos of its half-angle
  double radiance;     // 1 / its solid angle
  double operator()(Vec3 o) const {
    if (!sun) return 1.0;
    return dot(o, dir) >= cos_radius ? radiance : 0.0;
  }
};

Lighting lighting(bool sun) {
  const double c = std::cos(kSunHalfAngle);
  return {sun, spherical_direction(kSunTheta, kPi), c, 1 / (2 * kPi * (1 - c))};
}

struct Moments {
  double sum = 0, sum_sq = 0, seconds = 0;
};

// One batch of the one-sample estimator with the NDF (vndf_on false) or the vNDF sampler.
void batch(bool vndf_on, const mg::GrainField& f, const mg::MicroSurface& grain, const Lighting& light, Vec3 i,
           std::uint64_t seed, Moments& acc) {
  Rng rng(seed);
  double s = 0, s2 = 0;
  const double t0 = bench::thread_cpu_seconds();
  for (std::uint64_t k = 0; k < kBatch; ++k) {
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    const Vec3 m = vndf_on ? vndf().sample(f, i, u1, u2, u3) : mg::sample_ndf(f, u1, u2);
    const double im = dot(i, m);
    double w = 0;
    if (im > 0) {
      const Vec3 o = 2 * im * m - i;
      const double radiance = light(o);
      if (o.z > 0 && radiance > 0) {
        const double pdf_m = vndf_on ? mg::visible_ndf(f, i, m) : mg::ndf_pdf(f, m);
        if (pdf_m > 0) w = mg::gdist_grain_specular(f, grain, i, o) * o.z * radiance * 4 * im / pdf_m;
      }
    }
    s += w;
    s2 += w * w;
  }
  acc.seconds += bench::thread_cpu_seconds() - t0;
  acc.sum += s;
  acc.sum_sq += s2;
}

void bm_pair(benchmark::State& state, double tau0, double beta, bool sun, double theta_i_deg) {
  const mg::GrainField f{tau0, beta, beta};
  mg::MicroSurface grain;
  grain.type = mg::MicroSurface::Type::Conductor;
  grain.eta = 0.18299;
  grain.kappa = 3.4242;
  const Lighting light = lighting(sun);
  const Vec3 i = spherical_direction(theta_i_deg * kDeg, 0.0);
  vndf();  // the sigma^-1 table, built outside the timed loop
  Moments ndf, vn;
  // Every call (repetition) draws new samples: seeds (call << 32) + batch.
  static std::uint64_t calls = 0;
  std::uint64_t seed = ++calls << 32;
  bool vndf_first = false;
  for (auto _ : state) {
    for (int k = 0; k < 2; ++k) {
      const bool v = (k == 0) == vndf_first;
      batch(v, f, grain, light, i, seed, v ? vn : ndf);
    }
    ++seed;
    vndf_first = !vndf_first;
  }
  const double n = static_cast<double>(kBatch) * static_cast<double>(state.iterations());
  auto var = [n](const Moments& a) { return (a.sum_sq - a.sum * a.sum / n) / (n - 1); };
  const double var_ndf = var(ndf), var_vndf = var(vn);
  state.counters["mean_ndf"] = ndf.sum / n;
  state.counters["mean_vndf"] = vn.sum / n;
  state.counters["var_ndf"] = var_ndf;
  state.counters["var_vndf"] = var_vndf;
  state.counters["ndf_ns"] = 1e9 * ndf.seconds / n;
  state.counters["vndf_ns"] = 1e9 * vn.seconds / n;
  state.counters["var_ratio"] = var_ndf / var_vndf;
  state.counters["time_ratio"] = vn.seconds / ndf.seconds;
  state.counters["eff_ratio"] = (var_ndf * ndf.seconds) / (var_vndf * vn.seconds);
  state.counters["samples"] = n;
}

}  // namespace

int main(int argc, char** argv) {
  // (tau0, beta): the paper's Fig. 7 materials (0.4, 3) and (0.9, 0.3), and one between.
  const double materials[][2] = {{0.4, 3.0}, {0.6, 1.0}, {0.9, 0.3}};
  for (const auto& mat : materials)
    for (bool sun : {false, true})
      for (double t : {0.0, 20.0, 40.0, 60.0, 70.0, 80.0, 85.0}) {
        char name[128];
        std::snprintf(name, sizeof name, "pair/tau0:%g/beta:%g/%s/theta_i:%g", mat[0], mat[1], sun ? "sun" : "sky", t);
        benchmark::RegisterBenchmark(name, bm_pair, mat[0], mat[1], sun, t)
            ->MinTime(0.3)->UseRealTime()->Unit(benchmark::kMillisecond);
      }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
