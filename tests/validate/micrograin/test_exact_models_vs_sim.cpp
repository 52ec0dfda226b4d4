// The exact micrograin models that only the default suite compared with the
// simulation, now in ctest too (issue #15's exact two-direction visibility, the
// vNDF paper's Eq. 26):
// - pore_visibility_union: the joint visibility of a pore point toward i and o;
// - gdist_grain_union and gdist_base_union: the order-1 BRDF (vNDF Eq. 1) with
//   the two-direction union masking, on the grains and on the base;
// - phi_conditional_eq26: the azimuth the vNDF sampler's triangle cut draws given theta'.
// Each simulates with a fixed seed and 16 batches (kept), and is judged as
// `mcref validate` judges an exact model (validate/metrics.h: the sign-flip test
// over the batches, exact whatever the cells' correlation, at alpha = 0.001, and
// the Sidak bound on max |z|). The same model moved by a few standard errors
// per cell must FAIL, so each test can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {

constexpr double kAlpha = 0.001;

std::vector<Table> run(const Experiment& ex) {
  SimulateOptions o;
  o.threads = 2;
  o.quiet = true;
  o.keep_batch_values = true;
  return simulate(ex, o);
}

const Table& table(const std::vector<Table>& tables, const std::string& name) {
  for (const Table& t : tables)
    if (t.name == name) return t;
  throw std::runtime_error("no table " + name);
}

// The verdict of `model` (exact) on `t`, its values scaled by `scale`.
Verdict verdict(const Table& t, const std::string& model, const Experiment& ex, double scale = 1) {
  const ModelInfo* info = find_model(model);
  EXPECT_TRUE(info && info->exact) << model;
  std::vector<double> m = evaluate_model(model, t, ex);
  EXPECT_TRUE(evaluate_model_stderr(model, t, ex, m).empty()) << model << " has noise of its own";
  for (double& v : m) v *= scale;
  const Comparison c = compare(t.values(), t.stderrs(), m, t.batches, {}, t.channels(), t.batch_values);
  const Verdict v = judge(c, true, kAlpha, 0);
  std::printf("[ model    ] %-22s x %.3f on %-20s %4zu cells, %s: %s: %s\n", model.c_str(), scale, t.name.c_str(),
              c.cells, c.joint_test.c_str(), v.status.c_str(), v.reason.c_str());
  EXPECT_EQ(c.joint_test, "sign-flip") << model;
  return v;
}

// A shift of `sigmas` median relative standard errors of the table's cells.
double shifted(const Table& t, double sigmas) {
  std::vector<double> rel;
  for (std::size_t i = 0; i < t.cells(); ++i)
    if (t.value(i) > 0 && t.stderr_of(i) > 0) rel.push_back(t.stderr_of(i) / t.value(i));
  EXPECT_FALSE(rel.empty()) << t.name;
  if (rel.empty()) return 1;
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(rel.size() / 2), rel.end());
  return 1 + sigmas * rel[rel.size() / 2];
}

// `model` passes on `t`, and the same model moved by 4 median relative standard errors fails.
void expect_exact_and_resolved(const Table& t, const std::string& model, const Experiment& ex) {
  EXPECT_EQ(verdict(t, model, ex).status, "pass") << model;
  EXPECT_EQ(verdict(t, model, ex, shifted(t, 4)).status, "FAIL") << model;
}

const char* kField = "[geometry]\nkind = \"micrograin\"\ntau0 = 0.5\nbeta = 1.0\n";

}  // namespace

// Seed 7101, 16 batches (fields of tile 40) of 30 000 base points per
// direction pair: theta_i 30 and 60 deg, theta_o 30, 60, 80 deg, phi 0, 90, 180 deg.
TEST(ExactModelsVsSim, PoreVisibilityUnion) {
  const Experiment ex = parse_experiment(std::string(kField) +
                                             "tile = 40\n[run]\nseed = 7101\nbatches = 16\n[[measure]]\n"
                                             "quantity = \"pore_visibility\"\ntheta_i_deg = [30, 60]\n"
                                             "theta_o_deg = [30, 60, 80]\nphi_deg = [0, 90, 180]\nsamples = 30000\n",
                                         "pore_visibility.toml");
  const std::vector<Table> tables = run(ex);
  const Table& t = table(tables, "pore_visibility");
  expect_exact_and_resolved(t, "pore_visibility_union", ex);
}

// Seed 7102, 16 batches (fields of tile 80) of 20 000 paths per direction;
// grey Lambertian grains (0.8) on a Lambertian base (0.5); theta_i 30 and
// 60 deg, 6 x 6 outgoing bins.
TEST(ExactModelsVsSim, OrderOneBrdfWithTheUnionMasking) {
  const Experiment ex = parse_experiment(
      std::string(kField) +
          "tile = 80\n[material.grain]\ntype = \"lambertian\"\nalbedo = 0.8\n[material.base]\ntype = \"lambertian\"\n"
          "albedo = 0.5\n[run]\nseed = 7102\nbatches = 16\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30, 60]\n"
          "theta_o_bins = 6\nphi_bins = 6\nsamples = 20000\n",
      "brdf.toml");
  const std::vector<Table> tables = run(ex);
  for (const char* part : {"grain", "base"}) {
    expect_exact_and_resolved(table(tables, std::string("brdf_order1_") + part), std::string("gdist_") + part + "_union",
                              ex);
  }
}

// Seed 7103, 16 batches of 50 000 draws per (theta_i', theta'): theta_i' 30
// and 85 deg (no shadow and a deep one), theta' 20 and 80 deg, 24 azimuth bins.
TEST(ExactModelsVsSim, PhiConditionalEq26) {
  const Experiment ex = parse_experiment(std::string(kField) +
                                             "tile = 10\n[run]\nseed = 7103\nbatches = 16\n[[measure]]\n"
                                             "quantity = \"phi_conditional\"\ntheta_i_deg = [30, 85]\n"
                                             "theta_m_deg = [20, 80]\nphi_bins = 24\nsamples = 50000\n",
                                         "phi_conditional.toml");
  const std::vector<Table> tables = run(ex);
  const Table& t = table(tables, "phi_conditional");
  expect_exact_and_resolved(t, "phi_conditional_eq26", ex);
}
