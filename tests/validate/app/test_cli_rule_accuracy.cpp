// mcref validate reports the accuracy of the micrograin cell rule
// (ModelAccuracy, validate/model_evaluation.h) in results.json: a
// micrograin_brdf check carries rule_accuracy (its 2 x 2 cells, all converged),
// a check whose family uses fixed rules does not, and no warning is printed.
#include "tests/validate/app/cli_fixture.h"

using namespace mcref_test;

TEST_F(Cli, ResultsCarryTheCellRuleAccuracy) {
  std::string exp = experiment("tau0 = 0.5\nbeta = 1.0\n", "",
                               "quantity = \"brdf\"\ntheta_i_deg = [30]\ntheta_o_bins = 2\nphi_bins = 2\nsamples = 200\n"
                               "\n[[measure]]\nquantity = \"tau_plus\"\ntheta_i_deg = [30]\nsamples = 200\n");
  exp.insert(exp.find("[run]"), "[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"lambertian\"\n\n");
  write("x.toml", exp);
  write("s.toml",
        "[suite]\nname = \"s\"\n\n[[case]]\nname = \"c\"\nexperiment = \"x.toml\"\n\n"
        "[[case.check]]\ntable = \"brdf\"\nmodel = \"gdist_total_union\"\n\n"
        "[[case.check]]\ntable = \"tau_plus\"\nmodel = \"tau_plus_eq22\"\n");
  const Result r = mcref("validate " + quote(path("s.toml")) + " -o " + quote(path("out")));
  ASSERT_LE(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const std::string json = slurp(path("out/results.json"));
  const std::size_t brdf = json.find("\"model\": \"gdist_total_union\""), tau = json.find("\"model\": \"tau_plus_eq22\"");
  ASSERT_NE(brdf, std::string::npos) << json;
  ASSERT_NE(tau, std::string::npos) << json;
  // One integral per (theta_o, phi) cell, all channels: 2 x 2.
  const std::size_t acc = json.find("\"rule_accuracy\": {\"target\": 5e-07, \"integrals\": 4, \"unconverged\": 0,");
  ASSERT_NE(acc, std::string::npos) << json;
  EXPECT_GT(acc, brdf);
  EXPECT_EQ(json.find("\"rule_accuracy\"", acc + 1), std::string::npos) << "tau_plus_eq22 reported a rule accuracy";
}
