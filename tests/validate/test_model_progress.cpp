// validate/model_evaluation: a long model evaluation reports its progress in
// table cells through the calling thread's sink, and reports every cell once,
// on any number of threads (the micrograin BRDF and albedo evaluators). The
// same evaluators report their cell rule's accuracy (ModelAccuracy) to the
// calling thread's scope: one integral per brdf cell (all channels) and per
// albedo direction, all converged, the same on any number of threads; and
// ModelAccuracy merges in any order to the same result.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <mutex>

#include "sim/experiment/experiment.h"
#include "sim/tally/brdf_tally.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {
std::size_t reported_cells(const std::string& model, const Table& t, const Experiment& ex, ModelAccuracy& accuracy) {
  std::mutex lock;
  std::size_t sum = 0, calls = 0;
  const CellProgressScope scope([&](std::size_t n) {
    const std::lock_guard<std::mutex> guard(lock);
    sum += n;
    ++calls;
  });
  const ModelAccuracyScope accuracy_scope(&accuracy);
  evaluate_model(model, t, ex);
  EXPECT_GT(calls, 1u) << model << " on " << t.name << ": progress in one step only";
  return sum;
}
}  // namespace

TEST(ModelProgress, MicrograinBrdfAndAlbedoReportEveryCellOnce) {
  const Experiment ex = parse_experiment(
      "[geometry]\nkind = \"micrograin\"\ntau0 = 0.5\nbeta = 1.0\ntile = 20\n"
      "[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"lambertian\"\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0, 40]\nsamples = 10\n",
      "progress.toml");
  BrdfLayout l;
  l.order1_classes = {"grain", "base"};
  l.theta_o_bins = 3;
  l.phi_bins = 2;
  std::vector<ModelAccuracy> first;  // on one thread
  for (const int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::size_t checked = 0;
    for (const Table& t : make_brdf_tables("brdf", {0.0, 0.7}, {0.0}, l)) {
      if (t.name != "brdf_order1_grain" && t.name != "brdf_albedo") continue;
      const bool albedo = t.quantity == "albedo";
      const std::string model = albedo ? "gdist_albedo" : "gdist_grain_union";
      ModelAccuracy a;
      EXPECT_EQ(reported_cells(model, t, ex, a), t.cells()) << t.name << ", " << threads << " threads";
      // brdf: a cell's 3 channels; albedo: a direction's components and channels.
      const std::size_t per_integral = albedo ? t.axes[2].size() * t.axes[3].size() : 3;
      EXPECT_EQ(a.integrals, t.cells() / per_integral) << t.name;
      EXPECT_EQ(a.unconverged, 0u) << t.name;
      EXPECT_GT(a.worst_error, 0) << t.name;
      EXPECT_LE(a.worst_error, a.target) << t.name;
      if (threads == 1) {
        first.push_back(a);
      } else if (checked < first.size()) {
        EXPECT_EQ(a.worst_error, first[checked].worst_error) << t.name;
        EXPECT_EQ(a.worst_cell, first[checked].worst_cell) << t.name;
      }
      ++checked;
    }
    EXPECT_EQ(checked, 2u);
  }
}

TEST(ModelAccuracy, MergeIsOrderIndependent) {
  ModelAccuracy a, b;
  a.add(7, 2e-7, true, 5e-7);
  a.add(3, 4e-6, false, 5e-7);
  b.add(1, 4e-6, false, 5e-7);  // ties with cell 3: the lower cell is the worst
  b.add(9, 1e-7, true, 5e-7);
  ModelAccuracy ab = a, ba = b;
  ab.merge(b);
  ba.merge(a);
  for (const ModelAccuracy& m : {ab, ba}) {
    EXPECT_EQ(m.integrals, 4u);
    EXPECT_EQ(m.unconverged, 2u);
    EXPECT_EQ(m.worst_error, 4e-6);
    EXPECT_EQ(m.worst_cell, 1u);
    EXPECT_EQ(m.target, 5e-7);
  }
}

TEST(ModelAccuracy, ReachesTheInnermostScopeOnly) {
  ModelAccuracy outer, inner, one;
  one.add(0, 1e-3, false, 5e-7);
  {
    const ModelAccuracyScope a(&outer);
    {
      const ModelAccuracyScope b(&inner);
      report_model_accuracy(one);
    }
    report_model_accuracy(one);
    report_model_accuracy(one);
  }
  report_model_accuracy(one);  // no scope: nothing happens
  EXPECT_EQ(inner.integrals, 1u);
  EXPECT_EQ(outer.integrals, 2u);
}

TEST(ModelProgress, NoSinkIsANoOpAndScopesNest) {
  std::size_t outer = 0, inner = 0;
  {
    const CellProgressScope a([&](std::size_t n) { outer += n; });
    {
      const CellProgressScope b([&](std::size_t n) { inner += n; });
      cell_progress()(3);
    }
    cell_progress()(5);
  }
  cell_progress()(7);  // no sink: nothing happens
  EXPECT_EQ(inner, 3u);
  EXPECT_EQ(outer, 5u);
}
