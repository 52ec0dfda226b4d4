// validate/model_evaluation: a long model evaluation reports its progress in
// table cells through the calling thread's sink, and reports every cell once,
// on any number of threads (the micrograin BRDF and albedo evaluators).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <mutex>

#include "sim/experiment/experiment.h"
#include "sim/tally/brdf_tally.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {
std::size_t reported_cells(const std::string& model, const Table& t, const Experiment& ex) {
  std::mutex lock;
  std::size_t sum = 0, calls = 0;
  const CellProgressScope scope([&](std::size_t n) {
    const std::lock_guard<std::mutex> guard(lock);
    sum += n;
    ++calls;
  });
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
  for (const int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    int checked = 0;
    for (const Table& t : make_brdf_tables("brdf", {0.0, 0.7}, {0.0}, l)) {
      if (t.name != "brdf_order1_grain" && t.name != "brdf_albedo") continue;
      const std::string model = t.quantity == "albedo" ? "gdist_albedo" : "gdist_grain_union";
      EXPECT_EQ(reported_cells(model, t, ex), t.cells()) << t.name << ", " << threads << " threads";
      ++checked;
    }
    EXPECT_EQ(checked, 2);
  }
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
