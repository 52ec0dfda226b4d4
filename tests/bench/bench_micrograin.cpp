// Benchmarks of the micrograin field and its ray-casting estimators.
//
// 1. Rays/s of the tau_plus estimator (theta_i = 0, 60, 85 deg) and of the
//    ndf estimator (normal incidence) versus bare rtcIntersect1 on the same
//    Embree scene with exactly the same rays, on 1 and 2 threads. Realistic
//    field: tau0 = 0.5, beta = 0.8, tile 200 (~8.8k grains).
//      <q>/estimator : estimator_for(q).add_batch on a Measure (all of it:
//                      run_chunks, RNG, MicrograinField::intersect_unit, tallies)
//      <q>/trace     : run_chunks + uniform_top_origin + intersect_unit only
//      <q>/bare      : run_chunks + uniform_top_origin + rtcIntersect1 with
//                      tfar to the base plane, no wrapping
//      <q>/packets   : run_chunks + uniform_top_origins + packet_order +
//                      rtcIntersect16 on the same rays in the estimator's
//                      packets (tfar to the base plane, no wrapping)
//    All four draw the same origins: the chunk seeds are those add_batch uses
//    (StreamKey::with(0), then stream_seed({.., chunk})), and the direction is
//    the estimator's (-unit_direction(i), or unit_direction(-z) for ndf).
//      pair/<q>/...  : estimator, bare and packets batches back to back in
//                      every iteration, the order rotating (robust to load
//                      from other processes); counters "ratio" = estimator
//                      rays/s / bare rays/s (the target) and "packet_ratio" =
//                      estimator / packets, of wall time; "cpu_ratio" and
//                      "cpu_packet_ratio" the same of the process's CPU time.
// 2. Build time and resident-memory increase of a 10^6-grain field
//    (tau0 = 0.5, beta = 1, tile chosen so the expected count is 10^6).
// 3. Rays/s of tau_plus (estimator, trace, bare, pair) and g1 on that field
//    and on a tile-200 field with the same parameters (BVH size effects).
//
// A summary table with the ratios is printed after the benchmarks.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include "models/core/vec.h"
#include "sim/micrograin/estimator.h"
#include "sim/micrograin/micrograin_field.h"
#include "sim/micrograin/packet_order.h"

namespace {

using namespace mcref;

constexpr double kDeg = kPi / 180.0;
constexpr std::uint64_t kRays = 1 << 16;   // rays per batch (16 chunks of 4096)
constexpr std::uint64_t kBigRays = 1 << 16;
constexpr double kMinTime = 0.5;            // seconds per benchmark (pairs: 3x)
const StreamKey kKey{20240601, 0, 0};

// ---- fields ---------------------------------------------------------------

MicrograinGeometry geometry(double tau0, double beta, double tile) {
  MicrograinGeometry g;
  g.tau0 = tau0;
  g.beta_x = g.beta_y = beta;
  g.radius = 1.0;
  g.tile = tile;
  return g;
}

// Item 1: the realistic field.
const MicrograinField& realistic_field() {
  static const MicrograinField f(geometry(0.5, 0.8, 200.0), 11);
  return f;
}
// Item 3: same parameters as the big field, small tile.
const MicrograinField& small_field() {
  static const MicrograinField f(geometry(0.5, 1.0, 200.0), 13);
  return f;
}
// Tile side (in radii) whose expected grain count is n (beta = 1: unit = real).
double tile_for_count(double n, double tau0) { return std::sqrt(n * kPi / -std::log1p(-tau0)); }
std::unique_ptr<MicrograinField> g_big;  // built (and timed) by build/1e6; reused by item 3
const MicrograinField& big_field() {
  if (!g_big) g_big = std::make_unique<MicrograinField>(geometry(0.5, 1.0, tile_for_count(1e6, 0.5)), 17);
  return *g_big;
}

// ---- memory ---------------------------------------------------------------

// A field of /proc/self/status in KiB (-1 if absent).
long status_kib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::size_t n = std::strlen(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0 && line.size() > n && line[n] == ':') return std::stol(line.substr(n + 1));
  return -1;
}
// Resets VmHWM to the current RSS (Linux >= 4.0); false if not permitted.
bool reset_peak_rss() {
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

// ---- the three ray paths --------------------------------------------------

enum class Path { Estimator, Trace, Bare, Packets };
const char* path_name(Path p) {
  return p == Path::Estimator ? "estimator" : p == Path::Trace ? "trace" : p == Path::Bare ? "bare" : "packets";
}

Measure make_measure(const std::string& quantity, double theta_deg, std::uint64_t samples) {
  Measure m;
  m.quantity = quantity;
  m.name = quantity;
  m.theta_i = {theta_deg * kDeg};
  m.phi_i = {0.0};
  m.samples = static_cast<std::int64_t>(samples);
  if (quantity == "ndf") {
    m.theta_m_bins = 45;  // the experiment defaults
    m.phi_m_bins = 1;
  } else if (quantity == "g1") {
    m.theta_m_bins = 18;
    m.phi_m_bins = 18;
  }
  return m;
}

// The (micrograin) experiment an estimator sees for field f; one per field.
const Experiment& experiment_of(const MicrograinField& f) {
  static std::map<const MicrograinField*, std::unique_ptr<Experiment>> cache;
  auto& ex = cache[&f];
  if (!ex) ex = std::make_unique<Experiment>();
  ex->kind = "micrograin";
  ex->micrograin = f.geometry();  // (refreshed: a rebuilt field may reuse an address)
  ex->isotropic = !f.geometry().anisotropic();
  return *ex;
}

// The unit-space ray direction an estimator uses for its first direction.
Vec3 ray_direction(const MicrograinField& f, const std::string& quantity, double theta_deg) {
  if (quantity == "ndf") return unit_direction(f, {0, 0, -1});
  return -unit_direction(f, incident_direction(theta_deg * kDeg, 0.0));
}

// One batch of `samples` rays along one path; returns the number of grain
// hits (for the estimator: its estimate times samples, tau_plus only).
double run_batch(Path path, const MicrograinField& f, const std::string& quantity, double theta_deg,
                 std::uint64_t samples) {
  if (path == Path::Estimator) {
    const Estimator& e = estimator_for(quantity);
    const Measure m = make_measure(quantity, theta_deg, samples);
    const Experiment& ex = experiment_of(f);
    std::vector<Table> tables = e.make_tables(m, ex);
    e.add_batch(f, ex, m, kKey, tables);
    return tables[0].sum.empty() ? 0.0 : tables[0].sum[0] * static_cast<double>(samples);
  }
  const Vec3 d = ray_direction(f, quantity, theta_deg);
  if (path == Path::Trace) {
    const Sums s = run_chunks(samples, 1, kKey.with(0), [&](Rng& rng, std::uint64_t n, Sums& acc) {
      for (std::uint64_t k = 0; k < n; ++k)
        if (f.intersect_unit(uniform_top_origin(f, rng), d).kind == Hit::Kind::Grain) acc[0] += 1;
    });
    return s[0];
  }
  RTCScene scene = f.embree_scene();
  const float tfar = static_cast<float>(-1.0 / d.z);  // origins at z = 1, base plane at z = 0
  if (path == Path::Packets) {
    const Sums s = run_chunks(samples, 1, kKey.with(0), [&](Rng& rng, std::uint64_t n, Sums& acc) {
      thread_local std::vector<Vec3> origins, sorted;
      thread_local std::vector<std::uint32_t> order, cells;
      uniform_top_origins(f, rng, n, origins);
      packet_order(origins.data(), n, f.unit_side_x(), f.unit_side_y(), kPacketOriginsPerCell, order, sorted, cells);
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      alignas(64) RTCRayHit16 rh;
      alignas(64) int valid[16];
      for (std::uint64_t i = 0; i < n; i += 16) {
        for (std::uint64_t k = 0; k < 16; ++k) {
          valid[k] = i + k < n ? -1 : 0;
          if (i + k >= n) continue;
          const Vec3& o = sorted[i + k];
          rh.ray.org_x[k] = static_cast<float>(o.x);
          rh.ray.org_y[k] = static_cast<float>(o.y);
          rh.ray.org_z[k] = static_cast<float>(o.z);
          rh.ray.dir_x[k] = static_cast<float>(d.x);
          rh.ray.dir_y[k] = static_cast<float>(d.y);
          rh.ray.dir_z[k] = static_cast<float>(d.z);
          rh.ray.tnear[k] = 0.0f;
          rh.ray.tfar[k] = tfar;
          rh.ray.mask[k] = 0xFFFFFFFFu;
          rh.ray.flags[k] = 0;
          rh.ray.time[k] = 0;
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, scene, &context, &rh);
        for (std::uint64_t k = 0; k < 16 && i + k < n; ++k) acc[0] += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
      }
    });
    return s[0];
  }
  const Sums s = run_chunks(samples, 1, kKey.with(0), [&](Rng& rng, std::uint64_t n, Sums& acc) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::uint64_t k = 0; k < n; ++k) {
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
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) acc[0] += 1;
    }
  });
  return s[0];
}

// ---- benchmarks -----------------------------------------------------------

using FieldFn = const MicrograinField& (*)();

void bm_rays(benchmark::State& state, FieldFn field_fn, std::string quantity, Path path, double theta_deg,
             int threads, std::uint64_t samples) {
  const MicrograinField& f = field_fn();  // built outside the timed loop
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  double hits = 0;
  for (auto _ : state) {
    hits += run_batch(path, f, quantity, theta_deg, samples);
    benchmark::DoNotOptimize(hits);
  }
  const double rays = static_cast<double>(samples) * static_cast<double>(state.iterations());
  const char* unit = quantity == "g1" ? "samples/s" : "rays/s";
  state.counters[unit] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
  if (quantity == "tau_plus" || path != Path::Estimator) state.counters["hit_frac"] = hits / rays;
  state.counters["grains"] = static_cast<double>(f.grain_count());
}

// CPU time of the whole process (all threads), in seconds.
double process_cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Estimator, bare and packets in every iteration, the order rotating; the
// ratios are of the summed times.
void bm_pair(benchmark::State& state, FieldFn field_fn, std::string quantity, double theta_deg, int threads,
             std::uint64_t samples) {
  const MicrograinField& f = field_fn();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  using clock = std::chrono::steady_clock;
  const Path paths[3] = {Path::Estimator, Path::Bare, Path::Packets};
  double wall[3] = {0, 0, 0}, cpu[3] = {0, 0, 0}, hits[3] = {0, 0, 0};
  int first = 0;
  for (auto _ : state) {
    for (int k = 0; k < 3; ++k) {
      const int p = (first + k) % 3;
      const auto t0 = clock::now();
      const double c0 = process_cpu_seconds();
      hits[p] += run_batch(paths[p], f, quantity, theta_deg, samples);
      cpu[p] += process_cpu_seconds() - c0;
      wall[p] += std::chrono::duration<double>(clock::now() - t0).count();
    }
    first = (first + 1) % 3;
  }
  const double rays = static_cast<double>(samples) * static_cast<double>(state.iterations());
  state.counters["est_rays/s"] = rays / wall[0];
  state.counters["bare_rays/s"] = rays / wall[1];
  state.counters["packet_rays/s"] = rays / wall[2];
  state.counters["ratio"] = wall[1] / wall[0];
  state.counters["packet_ratio"] = wall[2] / wall[0];
  state.counters["cpu_ratio"] = cpu[1] / cpu[0];
  state.counters["cpu_packet_ratio"] = cpu[2] / cpu[0];
  if (quantity == "tau_plus") {
    state.counters["est_hit_frac"] = hits[0] / rays;
    state.counters["bare_hit_frac"] = hits[1] / rays;
    state.counters["packet_hit_frac"] = hits[2] / rays;
  }
}

void bm_build(benchmark::State& state, int threads, bool keep) {
  const MicrograinGeometry g = geometry(0.5, 1.0, tile_for_count(1e6, 0.5));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  double seconds = 0, rss_mib = 0, peak_mib = 0, grains = 0;
  bool peak_ok = true;
  for (auto _ : state) {
    state.PauseTiming();
    if (keep) g_big.reset();
    malloc_trim(0);  // hand freed heap back, so that RSS counts only this field
    const long rss0 = status_kib("VmRSS");
    peak_ok = reset_peak_rss() && peak_ok;
    const long hwm0 = status_kib("VmHWM");
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    auto field = std::make_unique<MicrograinField>(g, 17);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.PauseTiming();
    const long rss1 = status_kib("VmRSS");
    const long hwm1 = status_kib("VmHWM");
    rss_mib = std::max(rss_mib, (rss1 - rss0) / 1024.0);
    peak_mib = std::max(peak_mib, ((peak_ok ? hwm1 : std::max(hwm1, hwm0)) - rss0) / 1024.0);
    grains = static_cast<double>(field->grain_count());
    if (keep) g_big = std::move(field);
    field.reset();
    state.ResumeTiming();
  }
  state.counters["build_s"] = seconds / static_cast<double>(state.iterations());
  state.counters["rss_MiB"] = rss_mib;    // resident increase with the field alive
  state.counters["peak_MiB"] = peak_mib;  // peak resident increase during construction
  state.counters["peak_reset_ok"] = peak_ok ? 1 : 0;
  state.counters["grains"] = grains;
}

// ---- summary --------------------------------------------------------------

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  explicit SummaryReporter(bool color) : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular) {}
  std::map<std::string, std::map<std::string, double>> results;
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration || r.error_occurred) continue;
      auto& m = results[r.run_name.function_name];
      for (const auto& c : r.counters) m[c.first] = c.second.value;
    }
  }
  double get(const std::string& name, const std::string& counter) const {
    const auto it = results.find(name);
    if (it == results.end()) return NAN;
    const auto jt = it->second.find(counter);
    return jt == it->second.end() ? NAN : jt->second;
  }
};

std::string rays_name(const std::string& prefix, const std::string& q, Path p, double theta, int threads) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s%s/%s/theta:%g/threads:%d", prefix.c_str(), q.c_str(), path_name(p), theta,
                threads);
  return buf;
}
std::string pair_name(const std::string& q, double theta, int threads, const std::string& prefix = "") {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%spair/%s/theta:%g/threads:%d", prefix.c_str(), q.c_str(), theta, threads);
  return buf;
}

struct Case {
  std::string quantity;
  double theta;
};

}  // namespace

int main(int argc, char** argv) {
  const std::vector<Case> item1{{"tau_plus", 0}, {"tau_plus", 60}, {"tau_plus", 85}, {"ndf", 0}};
  const std::vector<int> thread_counts{1, 2};

  // 2. Build of the 10^6-grain field (first, while the process is small).
  benchmark::RegisterBenchmark("build/1e6_grains/threads:1", bm_build, 1, false)
      ->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("build/1e6_grains/threads:2", bm_build, 2, true)
      ->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

  // 1. Realistic field: estimator, trace, bare; then the back-to-back pairs.
  for (const Case& c : item1)
    for (int t : thread_counts)
      for (Path p : {Path::Estimator, Path::Trace, Path::Bare, Path::Packets})
        benchmark::RegisterBenchmark(rays_name("", c.quantity, p, c.theta, t).c_str(), bm_rays, &realistic_field,
                                     c.quantity, p, c.theta, t, kRays)
            ->MinTime(kMinTime)->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const Case& c : item1)
    for (int t : thread_counts)
      benchmark::RegisterBenchmark(pair_name(c.quantity, c.theta, t).c_str(), bm_pair, &realistic_field,
                                   c.quantity, c.theta, t, kRays)
          ->MinTime(3 * kMinTime)->UseRealTime()->Unit(benchmark::kMillisecond);

  // 3. BVH size: tile 200 vs 10^6 grains, same tau0 = 0.5, beta = 1; 2 threads.
  for (const auto& fld : {std::pair<std::string, FieldFn>{"tile200/", &small_field}, {"1e6/", &big_field}}) {
    for (double theta : {0.0, 60.0, 85.0}) {
      for (Path p : {Path::Estimator, Path::Trace, Path::Bare, Path::Packets})
        benchmark::RegisterBenchmark(rays_name(fld.first, "tau_plus", p, theta, 2).c_str(), bm_rays, fld.second,
                                     std::string("tau_plus"), p, theta, 2, kBigRays)
            ->MinTime(kMinTime)->UseRealTime()->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(pair_name("tau_plus", theta, 2, fld.first).c_str(), bm_pair, fld.second,
                                   std::string("tau_plus"), theta, 2, kBigRays)
          ->MinTime(3 * kMinTime)->UseRealTime()->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(rays_name(fld.first, "g1", Path::Estimator, 60, 2).c_str(), bm_rays, fld.second,
                                 std::string("g1"), Path::Estimator, 60.0, 2, kBigRays)
        ->MinTime(kMinTime)->UseRealTime()->Unit(benchmark::kMillisecond);
  }

  // Colour only on a terminal, unless --benchmark_color says otherwise.
  bool color = isatty(fileno(stdout));
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--benchmark_color=", 0) == 0) color = a.substr(18) == "true" || (a.substr(18) == "auto" && color);
  }
  SummaryReporter reporter(color);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  std::printf("\n== Summary: rays/s (M) and ratios to bare rtcIntersect1 (target >= 0.9) and to bare rtcIntersect16 ==\n");
  std::printf("%-22s %3s %10s %10s %10s %10s %10s %10s %10s %10s\n", "case", "thr", "estimator", "trace", "bare",
              "packets", "est/bare", "est/packet", "pair ratio", "pair pkt");
  for (const Case& c : item1)
    for (int t : thread_counts) {
      const double e = reporter.get(rays_name("", c.quantity, Path::Estimator, c.theta, t), "rays/s");
      const double tr = reporter.get(rays_name("", c.quantity, Path::Trace, c.theta, t), "rays/s");
      const double b = reporter.get(rays_name("", c.quantity, Path::Bare, c.theta, t), "rays/s");
      const double pk = reporter.get(rays_name("", c.quantity, Path::Packets, c.theta, t), "rays/s");
      const double pr = reporter.get(pair_name(c.quantity, c.theta, t), "ratio");
      const double pp = reporter.get(pair_name(c.quantity, c.theta, t), "packet_ratio");
      char label[64];
      std::snprintf(label, sizeof label, "%s theta=%g", c.quantity.c_str(), c.theta);
      std::printf("%-22s %3d %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f%s\n", label, t, e / 1e6, tr / 1e6,
                  b / 1e6, pk / 1e6, e / b, e / pk, pr, pp, (pr < 0.9 || e / b < 0.9) ? "  < 0.9" : "");
    }
  for (const char* name : {"build/1e6_grains/threads:1", "build/1e6_grains/threads:2"})
    std::printf("%s: grains %.0f, build %.2f s (target < 10), RSS +%.0f MiB, peak +%.0f MiB (target < 1024)\n", name,
                reporter.get(name, "grains"), reporter.get(name, "build_s"), reporter.get(name, "rss_MiB"),
                reporter.get(name, "peak_MiB"));
  std::printf("%-22s %10s %10s %10s   (M rays/s; beta = 1, 2 threads)\n", "tau_plus", "tile200", "1e6", "1e6/t200");
  for (double theta : {0.0, 60.0, 85.0}) {
    for (Path p : {Path::Estimator, Path::Trace, Path::Bare, Path::Packets}) {
      const double s = reporter.get(rays_name("tile200/", "tau_plus", p, theta, 2), "rays/s");
      const double l = reporter.get(rays_name("1e6/", "tau_plus", p, theta, 2), "rays/s");
      char label[64];
      std::snprintf(label, sizeof label, "theta=%g %s", theta, path_name(p));
      std::printf("%-22s %10.3f %10.3f %10.3f\n", label, s / 1e6, l / 1e6, l / s);
    }
    for (const char* counter : {"ratio", "packet_ratio"}) {
      const double s = reporter.get(pair_name("tau_plus", theta, 2, "tile200/"), counter);
      const double l = reporter.get(pair_name("tau_plus", theta, 2, "1e6/"), counter);
      char label[64];
      std::snprintf(label, sizeof label, "theta=%g pair %s", theta, counter);
      std::printf("%-22s %10.3f %10.3f\n", label, s, l);
    }
  }
  {
    const double s = reporter.get(rays_name("tile200/", "g1", Path::Estimator, 60, 2), "samples/s");
    const double l = reporter.get(rays_name("1e6/", "g1", Path::Estimator, 60, 2), "samples/s");
    std::printf("%-22s %10.3f %10.3f %10.3f  (M samples/s)\n", "g1 theta=60", s / 1e6, l / 1e6, l / s);
  }
  benchmark::Shutdown();
  return 0;
}
