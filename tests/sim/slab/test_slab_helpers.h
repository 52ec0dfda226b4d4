#pragma once
// Shared by the slab tests: run an experiment given as TOML text, compare a
// table with a slab model the way the suite does (exact: p >= 0.001 and the
// Sidak |z| bound at 0.001).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"

namespace slab_test {

// A slab: [geometry] kind = "slab" and `geometry` (keys, then the layers);
// 10 batches of 20 000 paths at theta_i = 20, 70 deg and phi_i = 0, 90 deg,
// 5 x 6 outgoing bins; `measure_extra`: more [[measure]] keys.
inline mcref::Experiment four_directions(const std::string& geometry, int seed, const std::string& measure_extra = "") {
  return mcref::parse_experiment("[geometry]\nkind = \"slab\"\n" + geometry + "[run]\nseed = " + std::to_string(seed) + R"(
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 70]
phi_i_deg = [0, 90]
theta_o_bins = 5
phi_bins = 6
samples = 20000
)" + measure_extra,
                                 "slab_test.toml");
}

// An OpenVDB slab of one SGGX surface-like layer (alpha 0.5, thickness 1,
// density 3) on a unit tile of 16 x 16 voxel columns and 4 voxel intervals in
// depth, for tests that vary its density laterally by editing the grids (as a
// density_vdb file would); `layer_extra`: more keys of the layer.
inline mcref::Experiment lateral_grid_experiment(const std::string& layer_extra = "") {
  return mcref::parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
lateral_voxels = 16
depth_voxels = 4
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 3.0
)" + layer_extra + R"([[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)",
                                 "lateral.toml");
}

inline std::vector<mcref::Table> run(const mcref::Experiment& ex, int threads = 2) {
  mcref::SimulateOptions o;
  o.threads = threads;
  o.quiet = true;
  return mcref::simulate(ex, o);
}

inline const mcref::Table& find(const std::vector<mcref::Table>& tables, const std::string& name) {
  for (const mcref::Table& t : tables)
    if (t.name == name) return t;
  throw std::runtime_error("no table " + name);
}

inline void expect_exact(const std::vector<mcref::Table>& tables, const std::string& table, const std::string& model,
                         const mcref::Experiment& ex) {
  const mcref::Table& t = find(tables, table);
  const std::vector<double> m = mcref::evaluate_model(model, t, ex);
  const mcref::Comparison c = mcref::compare(t.values(), t.stderrs(), m, t.batches, {}, t.channels());
  const mcref::Verdict v = mcref::judge(c, true, 1e-3, 0);
  EXPECT_EQ(v.status, "pass") << table << " vs " << model << ": " << v.reason;
  EXPECT_GT(c.cells, 0u);
}

// A conservative stack without substrate: the energy table against the white
// furnace (R + T_scattered = 1 - T_delta), and, with the delta lobe, R + T = 1
// to rounding for each of the `directions` incident directions (an analog walk
// conserves energy exactly).
inline void expect_white_furnace(const std::vector<mcref::Table>& t, const mcref::Experiment& ex, std::size_t directions) {
  expect_exact(t, "brdf_energy", "white_furnace", ex);
  const mcref::Table &r = find(t, "brdf_albedo"), &tr = find(t, "brdf_btdf_albedo");
  const std::size_t comps = r.axes[2].size();
  for (std::size_t d = 0; d < directions; ++d)
    for (int c = 0; c < 3; ++c) {
      const std::size_t total = (d * comps + comps - 1) * 3 + c;
      EXPECT_NEAR(r.value(total) + tr.value(total), 1.0, 1e-12);
    }
}

// Two independent simulations of the same medium: per cell, their difference
// over the quadrature of both standard errors (batch spread), judged as an
// exact model: p >= alpha (each colour channel's chi2 on its own, Bonferroni
// over them: a path's channels are one sample) and the Sidak |z| bound at
// alpha. `grey`: channel 0 only.
inline void expect_same(const std::vector<mcref::Table>& ta, const std::vector<mcref::Table>& tb,
                        const std::vector<std::string>& names, bool grey, double alpha = 1e-3) {
  for (const std::string& name : names) {
    const mcref::Table &a = find(ta, name), &b = find(tb, name);
    std::vector<double> diff(a.cells()), se(a.cells()), zero(a.cells(), 0.0);
    for (std::size_t i = 0; i < a.cells(); ++i) {
      diff[i] = a.value(i) - b.value(i);
      se[i] = std::hypot(a.stderr_of(i), b.stderr_of(i));
      if (grey && i % 3) diff[i] = NAN;
    }
    const mcref::Comparison c = mcref::compare(diff, se, zero, a.batches, {}, a.channels());
    const mcref::Verdict verdict = mcref::judge(c, true, alpha, 0);
    EXPECT_EQ(verdict.status, "pass") << name << ": " << verdict.reason;
    EXPECT_GT(c.cells, 0u) << name;
  }
}

// The same sums, bit for bit, on 1 and 2 threads.
// The same bits on 1, 2 and 3 threads (3: more threads than this machine's
// cores, and an odd count, so chunks finish in yet another order).
inline void expect_bit_identical_threads(const mcref::Experiment& ex) {
  const std::vector<mcref::Table> a = run(ex, 1);
  for (int threads : {2, 3}) {
    const std::vector<mcref::Table> b = run(ex, threads);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].sum, b[k].sum) << a[k].name << " on " << threads << " threads";
      EXPECT_EQ(a[k].sum_sq, b[k].sum_sq) << a[k].name << " on " << threads << " threads";
    }
  }
}

}  // namespace slab_test
