// The data-parallel slab walk (sim/slab/wave_walk.h) against the scalar walk
// (sim/slab/walk.h) on the same medium, for every phase function and every
// substrate: two independent simulations (seeds 41 and 42, 10 batches of
// 20 000 paths per incident direction), every cell of the BRDF, BTDF and
// per-component albedo and delta tables compared through the quadrature of
// both standard errors (RGB): p >= alpha and the Sidak |z| bound at alpha, with
// alpha = 0.01 / 62, 62 being the number of table comparisons below (a
// family-wise false-failure rate of 1 %; at alpha = 0.001 per table, about 6 %).
// Then the white furnace, thread-count independence and the config checks.
#include <cmath>

#include "sim/experiment/config_error.h"
#include "sim/slab/wave_walk.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

const char* const kPhases[] = {
    "phase = \"sggx_surface\"\nalpha = 0.4\nalbedo = [0.95, 0.8, 0.6]\nf0 = [1.0, 0.7, 0.4]\n",
    "phase = \"sggx_fiber\"\nalpha = 0.3\norientation_deg = [60, 30]\nalbedo = 0.9\n",
    "phase = \"hg\"\ng = 0.7\nalbedo = [0.9, 0.7, 0.5]\n",
    "phase = \"isotropic\"\nalbedo = 0.95\n",
    "phase = \"lambert_sphere\"\nalbedo = 0.9\n",
};
const char* const kSubstrates[] = {
    "substrate = \"none\"\n",
    "substrate = \"lambertian\"\nsubstrate_albedo = [0.8, 0.5, 0.3]\n",
    "substrate = \"conductor\"\n",
    "substrate = \"rough_conductor\"\nsubstrate_alpha = 0.3\n",
};

Experiment experiment(const std::string& substrate, const std::string& phase, const std::string& walk, int seed,
                      const std::string& measure_extra = "") {
  return parse_experiment("[geometry]\nkind = \"slab\"\nwalk = \"" + walk + "\"\n" + substrate +
                              "[[geometry.layer]]\nthickness = 1.0\noptical_thickness = 2.0\n" + phase +
                              "[run]\nseed = " + std::to_string(seed) + R"(
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 70]
phi_i_deg = [0, 90]
theta_o_bins = 5
phi_bins = 6
samples = 20000
)" + measure_extra,
                          "wave.toml");
}

constexpr double kAlpha = 0.01 / 62;

class WaveAgainstScalar : public testing::TestWithParam<std::tuple<int, int>> {};

}  // namespace

TEST_P(WaveAgainstScalar, SameTablesWithinStatistics) {
  const auto [phase, substrate] = GetParam();
  const Experiment scalar = experiment(kSubstrates[substrate], kPhases[phase], "scalar", 41);
  const Experiment wave = experiment(kSubstrates[substrate], kPhases[phase], "wave", 42);
  std::vector<std::string> names{"brdf", "brdf_albedo"};
  if (substrate == 0) names.insert(names.end(), {"brdf_btdf", "brdf_btdf_albedo", "brdf_btdf_delta"});  // unscattered
  if (substrate == 2) names.push_back("brdf_delta");  // the smooth conductor's mirror lobe
  slab_test::expect_same(slab_test::run(scalar), slab_test::run(wave), names, false, kAlpha);
}

INSTANTIATE_TEST_SUITE_P(PhasesAndSubstrates, WaveAgainstScalar,
                         testing::Combine(testing::Range(0, 5), testing::Range(0, 4)));

// The paper's depth cap (max_order) and the roulette from order 2 on.
TEST(WaveWalk, OrderCapAgreesWithScalar) {
  const std::string cap = "max_order = 2\n";
  slab_test::expect_same(slab_test::run(experiment(kSubstrates[1], kPhases[0], "scalar", 43, cap)),
                         slab_test::run(experiment(kSubstrates[1], kPhases[0], "wave", 44, cap)),
                         {"brdf", "brdf_albedo"}, false, kAlpha);
}

// A conservative layer: R + T_scattered = 1 - T_delta within statistics, and
// R + T = 1 exactly with the delta lobe (weights stay 1 in an analog walk).
TEST(WaveWalk, WhiteFurnace) {
  const Experiment ex = experiment(kSubstrates[0], "phase = \"sggx_surface\"\nalpha = 0.3\n", "wave", 45);
  slab_test::expect_white_furnace(slab_test::run(ex), ex, 4);
}

TEST(WaveWalk, BitIdenticalForAnyThreadCount) {
  slab_test::expect_bit_identical_threads(experiment(kSubstrates[3], kPhases[0], "wave", 46));
  slab_test::expect_bit_identical_threads(experiment(kSubstrates[0], kPhases[4], "wave", 47));
}

// walk = "wave" takes one homogeneous layer; anything else is a config error naming the key.
TEST(WaveWalk, RejectsWhatItDoesNotCover) {
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\n";
  const std::string run = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  for (const std::string& geometry : {"[geometry]\nkind = \"slab\"\nwalk = \"wave\"\n" + layer + layer + run,
                                      "[geometry]\nkind = \"slab\"\nwalk = \"wave\"\nbackend = \"openvdb\"\n" + layer + run}) {
    try {
      parse_experiment(geometry, "bad.toml");
      ADD_FAILURE() << "accepted: " << geometry;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("geometry.walk"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.toml"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(volume::wave_walk_unsupported(parse_experiment("[geometry]\nkind = \"slab\"\n" + layer + run, "ok.toml").slab), "");
}
