// The data-parallel slab walk (sim/slab/wave_walk.h) against the scalar walk
// (sim/slab/walk.h) on the same medium, for every phase function and every
// substrate, and on stacks of 2 and 3 layers: two independent simulations (seeds 41 and 42, 10 batches of
// 20 000 paths per incident direction), every cell of the BRDF, BTDF and
// per-component albedo and delta tables compared through the quadrature of
// both standard errors (RGB, each channel's chi2 on its own, Bonferroni over
// the three: a path's channels are one sample): p >= alpha and the Sidak |z| bound at alpha, with
// alpha = 0.01 / 218, 218 being the number of table comparisons below (a
// family-wise false-failure rate of 1 %). The same for the next-event estimators
// (walk.h) in both walks, for every phase function and substrate (seeds 101 and 102)
// and on the stacks (seeds 121 and 122).
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

// `layers`: the [[geometry.layer]] tables.
Experiment stack_experiment(const std::string& substrate, const std::string& layers, const std::string& walk, int seed,
                            const std::string& measure_extra = "") {
  return slab_test::four_directions("walk = \"" + walk + "\"\n" + substrate + layers, seed, measure_extra);
}

// One layer of optical thickness 2 with the keys `phase` (and more layers after it, if given).
Experiment experiment(const std::string& substrate, const std::string& phase, const std::string& walk, int seed,
                      const std::string& measure_extra = "") {
  return stack_experiment(substrate, "[[geometry.layer]]\nthickness = 1.0\noptical_thickness = 2.0\n" + phase, walk, seed,
                          measure_extra);
}

constexpr double kAlpha = 0.01 / 218;

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

// {phase, substrate, estimator}: next_event (0) or next_event_mis (1).
class WaveNextEventAgainstScalar : public testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(WaveNextEventAgainstScalar, SameTablesWithinStatistics) {
  const auto [phase, substrate, mis] = GetParam();
  const std::string geometry = std::string("estimator = \"") + (mis ? "next_event_mis" : "next_event") + "\"\n" + kSubstrates[substrate];
  std::vector<std::string> names{"brdf", "brdf_albedo"};
  if (substrate == 0) names.insert(names.end(), {"brdf_btdf", "brdf_btdf_albedo", "brdf_btdf_delta"});
  if (substrate == 2) names.push_back("brdf_delta");
  slab_test::expect_same(slab_test::run(experiment(geometry, kPhases[phase], "scalar", 101)),
                         slab_test::run(experiment(geometry, kPhases[phase], "wave", 102)), names, false, kAlpha);
}

INSTANTIATE_TEST_SUITE_P(PhasesSubstratesAndEstimators, WaveNextEventAgainstScalar,
                         testing::Combine(testing::Range(0, 5), testing::Range(0, 4), testing::Range(0, 2)));

// Stacks: {substrate, layers}; layers cross in the wave walk's scalar pass.
const char* const kStacks[][2] = {
    {"substrate = \"none\"\n",
     "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.2\nthickness = 0.5\ndensity = 1.0\nalbedo = [0.9, 0.7, 0.5]\n"
     "f0 = 0.6\n[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.5\norientation = [0, 1, 0.3]\nthickness = 1.5\n"
     "density = 2.0\nalbedo = 0.95\n"},
    {"substrate = \"lambertian\"\nsubstrate_albedo = [0.8, 0.5, 0.3]\n",
     "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.3\norientation_deg = [90, 0]\noptical_thickness = 0.7\n"
     "albedo = 0.8\n[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.6\noptical_thickness = 1.5\nalbedo = 0.9\n"},
    {"substrate = \"rough_conductor\"\nsubstrate_alpha = 0.3\n",
     "[[geometry.layer]]\nphase = \"hg\"\ng = 0.7\noptical_thickness = 1.0\nalbedo = [0.9, 0.7, 0.5]\n"
     "[[geometry.layer]]\nphase = \"hg\"\ng = -0.3\noptical_thickness = 0.5\nalbedo = 0.95\n"},
    {"substrate = \"conductor\"\n",
     "[[geometry.layer]]\nphase = \"isotropic\"\noptical_thickness = 0.3\nalbedo = 0.95\n"
     "[[geometry.layer]]\nphase = \"isotropic\"\ndensity = 0\nthickness = 0.5\n"
     "[[geometry.layer]]\nphase = \"isotropic\"\noptical_thickness = 1.0\nalbedo = 0.6\n"},
};

class WaveStackAgainstScalar : public testing::TestWithParam<int> {};

TEST_P(WaveStackAgainstScalar, SameTablesWithinStatistics) {
  const int k = GetParam();
  const Experiment scalar = stack_experiment(kStacks[k][0], kStacks[k][1], "scalar", 61);
  const Experiment wave = stack_experiment(kStacks[k][0], kStacks[k][1], "wave", 62);
  std::vector<std::string> names{"brdf", "brdf_albedo"};
  if (k == 0) names.insert(names.end(), {"brdf_btdf", "brdf_btdf_albedo", "brdf_btdf_delta"});
  if (k == 3) names.push_back("brdf_delta");
  slab_test::expect_same(slab_test::run(scalar), slab_test::run(wave), names, false, kAlpha);
}

INSTANTIATE_TEST_SUITE_P(Stacks, WaveStackAgainstScalar, testing::Range(0, 4));

// The next-event estimators on the stacks (seeds 121 and 122): in the wave walk, a
// vector stage computes their tallies through 2 and 3 layers, an empty one among them.
class WaveStackNextEventAgainstScalar : public testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(WaveStackNextEventAgainstScalar, SameTablesWithinStatistics) {
  const auto [k, mis] = GetParam();
  const std::string estimator = std::string("estimator = \"") + (mis ? "next_event_mis" : "next_event") + "\"\n";
  const Experiment scalar = stack_experiment(estimator + kStacks[k][0], kStacks[k][1], "scalar", 121);
  const Experiment wave = stack_experiment(estimator + kStacks[k][0], kStacks[k][1], "wave", 122);
  std::vector<std::string> names{"brdf", "brdf_albedo"};
  if (k == 0) names.insert(names.end(), {"brdf_btdf", "brdf_btdf_albedo", "brdf_btdf_delta"});
  if (k == 3) names.push_back("brdf_delta");
  slab_test::expect_same(slab_test::run(scalar), slab_test::run(wave), names, false, kAlpha);
}

INSTANTIATE_TEST_SUITE_P(StacksAndEstimators, WaveStackNextEventAgainstScalar,
                         testing::Combine(testing::Range(0, 4), testing::Range(0, 2)));

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
  const Experiment two = experiment(kSubstrates[0],
                                    "phase = \"sggx_surface\"\nalpha = 0.3\n[[geometry.layer]]\nphase = \"sggx_fiber\"\n"
                                    "alpha = 0.6\norientation = [0, 1, 0.3]\noptical_thickness = 1.0\n",
                                    "wave", 48);
  slab_test::expect_white_furnace(slab_test::run(two), two, 4);
}

TEST(WaveWalk, BitIdenticalForAnyThreadCount) {
  slab_test::expect_bit_identical_threads(experiment(kSubstrates[3], kPhases[0], "wave", 46));
  slab_test::expect_bit_identical_threads(experiment(kSubstrates[0], kPhases[4], "wave", 47));
  slab_test::expect_bit_identical_threads(stack_experiment(kStacks[1][0], kStacks[1][1], "wave", 49));
  slab_test::expect_bit_identical_threads(experiment(std::string("estimator = \"next_event_mis\"\n") + kSubstrates[1], kPhases[0], "wave", 50));
}

// walk = "wave" takes up to 4 layers of one phase function; anything
// else is a config error naming the key.
TEST(WaveWalk, RejectsWhatItDoesNotCover) {
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\n";
  const std::string flakes = "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.3\n";
  const std::string run = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  for (const std::string& geometry : {"[geometry]\nkind = \"slab\"\nwalk = \"wave\"\n" + layer + layer + layer + layer + layer + run,
                                      "[geometry]\nkind = \"slab\"\nwalk = \"wave\"\n" + flakes + layer + run}) {
    try {
      parse_experiment(geometry, "bad.toml");
      ADD_FAILURE() << "accepted: " << geometry;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("geometry.walk"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.toml"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(volume::wave_walk_unsupported(parse_experiment("[geometry]\nkind = \"slab\"\n" + layer + run, "ok.toml").slab), "");
  const std::string surface = "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.5\n";
  EXPECT_EQ(volume::wave_walk_unsupported(
                parse_experiment("[geometry]\nkind = \"slab\"\n" + flakes + surface + run, "ok.toml").slab),
            "");
  EXPECT_EQ(volume::wave_walk_unsupported(parse_experiment("[geometry]\nkind = \"slab\"\n" + layer + layer + layer + layer + run, "ok.toml").slab), "");
  EXPECT_EQ(volume::wave_walk_unsupported(
                parse_experiment("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\n" + layer + run, "ok.toml").slab),
            "");  // OpenVDB slabs: test_slab_wave_grid.cpp
}
