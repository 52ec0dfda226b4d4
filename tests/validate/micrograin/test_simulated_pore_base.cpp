// validate/micrograin/simulated_pore_base: an exact identity of the measured pore
// visibility. No grain lies above a pore, so every pore point sees straight
// up: at normal incidence the base's mirror lobe seen through the pores is
// exactly (1 - tau0) E_delta, with no Monte Carlo noise (standard error 0).
#include <gtest/gtest.h>

#include "sim/experiment/experiment.h"
#include "sim/tally/brdf_tally.h"
#include "validate/micrograin/simulated_pore_base.h"

using namespace mcref;

TEST(SimulatedPoreBase, NormalIncidenceMirrorLobeIsExact) {
  const Experiment ex = parse_experiment(
      "[geometry]\nkind = \"micrograin\"\ntau0 = 0.6\nbeta = 0.7\ntile = 20\n"
      "[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"conductor\"\npreset = \"gold\"\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0]\nsamples = 10\n",
      "pores.toml");
  BrdfLayout l;
  l.order1_classes = {"grain", "base"};
  l.theta_o_bins = 2;
  l.phi_bins = 2;
  const std::vector<Table> tables = make_brdf_tables("brdf", {0.0}, {0.0}, l);
  const BaseReflection base{[](int, Vec3, Vec3) { return 0.0; }, [](int ch, Vec3) { return 0.3 * (ch + 1); }};
  int checked = 0;
  for (const Table& t : tables) {
    if (t.name != "brdf_delta" && t.name != "brdf_albedo") continue;
    ++checked;
    const PoreBase& p = simulated_pore_base(t, ex, base);
    const std::size_t base_component = 1, total = t.axes[2].size() - 1;
    for (std::size_t ch = 0; ch < 3; ++ch)
      for (const std::size_t comp : {base_component, total}) {
        EXPECT_NEAR(p.values[t.index({0, 0, comp, ch})], 0.4 * 0.3 * (ch + 1), 1e-12) << t.name;
        // Every pore point gives the same energy (0.3 is not a binary fraction,
        // so the sums carry rounding): the estimate has no spread.
        EXPECT_NEAR(p.stderrs[t.index({0, 0, comp, ch})], 0.0, 1e-12) << t.name;
      }
  }
  EXPECT_EQ(checked, 2);  // a renamed table would leave the loop empty
}
