// validate/spheres: volumetric_mc, the volumetric half-space simulated with
// more paths, is a Monte Carlo estimate itself: its standard errors enter the
// checks in quadrature (before, none were given, and its chi2/dof was inflated
// by about 1 / kReferencePathFactor). The other sphere models have no noise.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "validate/model_evaluation.h"

using namespace mcref;

TEST(VolumetricReference, CarriesItsStandardErrors) {
  const Experiment ex = parse_experiment(
      "[geometry]\nkind = \"spheres\"\nplacement = \"poisson\"\nvolume_fraction = 0.005\nalbedo = 0.8\ntile = 200\n"
      "transmission_threshold = 1e-3\n[run]\nseed = 3\nbatches = 4\n[[measure]]\nquantity = \"brdf\"\n"
      "theta_i_deg = [0, 60]\ntheta_o_bins = 4\nphi_bins = 4\nsamples = 400\n",
      "x.toml");
  SimulateOptions o;
  o.quiet = true;
  const std::vector<Table> tables = simulate(ex, o);
  const Table* t = nullptr;
  for (const Table& x : tables)
    if (x.name == "brdf") t = &x;
  ASSERT_TRUE(t);
  const std::vector<double> values = evaluate_model("volumetric_mc", *t, ex);
  const std::vector<double> se = evaluate_model_stderr("volumetric_mc", *t, ex, values);
  ASSERT_EQ(se.size(), values.size());
  std::size_t with_signal = 0;
  for (std::size_t i = 0; i < se.size(); ++i) {
    if (values[i] > 0) {
      ++with_signal;
      EXPECT_GT(se[i], 0.0) << "cell " << i;
      EXPECT_LE(se[i], values[i]) << "cell " << i;  // (equal only when a single batch saw the cell)
    } else {
      EXPECT_EQ(se[i], 0.0) << "cell " << i;  // every batch gave 0 there
    }
  }
  EXPECT_GT(with_signal, se.size() / 2);
  EXPECT_TRUE(evaluate_model_stderr("reference_three_term", *t, ex, evaluate_model("reference_three_term", *t, ex)).empty());
}
