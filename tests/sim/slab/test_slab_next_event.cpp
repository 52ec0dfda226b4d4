// The next-event estimators of the slab walk ([geometry] estimator = "next_event"
// and "next_event_mis", sim/slab/walk.h) against the analog one on the same medium: two independent
// simulations (seeds 51 and 52, 10 batches of 20 000 paths per incident
// direction, 4 incident directions), every cell of the BRDF and BTDF (total and
// per order), albedo and delta tables compared through the quadrature of both
// standard errors (RGB): p >= alpha and the Sidak |z| bound at alpha, with
// alpha = 0.01 / 166, 166 being the number of table comparisons below (a
// family-wise false-failure rate of 1 %). Cells the analog walk never reached
// (zero in every batch: no standard error) are left out of the chi^2 and
// checked one by one: weights never exceed 1, so N paths per direction reach
// a cell of energy E (the next-event value times the bin's projected solid
// angle) at least N E times in expectation, and none arrive with probability
// at most exp(-N E); the test asks N E <= ln(cells / alpha) in every such cell. Media: SGGX surface and fibre flakes,
// one and two layers, HG, isotropic and Lambert-sphere layers, every substrate, and an
// OpenVDB stack of a linear and a tabulated depth profile (escapes through columns).
// Then the escape probability itself, the white furnace, thread-count
// independence and the config checks.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "sim/experiment/config_error.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/escape.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

struct Medium {
  const char* geometry;  // [geometry] keys and layers
  int substrate;         // 0 none, 1 lambertian or rough conductor, 2 smooth conductor
};

const Medium kMedia[] = {
    {"[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.4\noptical_thickness = 2.0\n"
     "albedo = [0.95, 0.8, 0.6]\nf0 = [1.0, 0.7, 0.4]\n", 0},
    {"[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.3\norientation_deg = [60, 30]\noptical_thickness = 2.0\n"
     "albedo = 0.9\n", 0},
    {"[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.2\nthickness = 0.5\ndensity = 1.0\nalbedo = [0.9, 0.7, 0.5]\n"
     "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.5\norientation = [0, 1, 0.3]\nthickness = 1.5\ndensity = 2.0\n"
     "albedo = 0.95\n", 0},
    {"substrate = \"lambertian\"\nsubstrate_albedo = [0.8, 0.5, 0.3]\n"
     "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.3\norientation_deg = [90, 0]\noptical_thickness = 0.7\nalbedo = 0.8\n"
     "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.6\noptical_thickness = 1.5\nalbedo = 0.9\nf0 = 0.5\n", 1},
    {"substrate = \"rough_conductor\"\nsubstrate_alpha = 0.3\n"
     "[[geometry.layer]]\nphase = \"hg\"\ng = 0.7\noptical_thickness = 1.0\nalbedo = [0.9, 0.7, 0.5]\n", 1},
    {"substrate = \"conductor\"\n[[geometry.layer]]\nphase = \"isotropic\"\noptical_thickness = 0.5\nalbedo = 0.95\n", 2},
    {"[[geometry.layer]]\nphase = \"lambert_sphere\"\noptical_thickness = 0.3\nalbedo = 0.9\n", 0},
    {"backend = \"openvdb\"\ndepth_voxels = 16\n"
     "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.4\norientation_deg = [50, 20]\noptical_thickness = 1.5\n"
     "albedo = [0.95, 0.8, 0.6]\nprofile = \"linear\"\nprofile_top = 0.3\nprofile_bottom = 1.7\n"
     "[[geometry.layer]]\nphase = \"hg\"\ng = 0.5\noptical_thickness = 1.0\nalbedo = 0.9\n"
     "profile = \"table\"\nprofile_table = [1.0, 0.2, 1.5, 0.6]\n", 0},
};

Experiment experiment(const Medium& m, const std::string& estimator, int seed, const std::string& measure_extra = "") {
  return slab_test::four_directions("estimator = \"" + estimator + "\"\n" + m.geometry, seed, measure_extra);
}

std::vector<std::string> tables_of(const Medium& m) {
  std::vector<std::string> n{"brdf", "brdf_order1_volume", "brdf_order2", "brdf_order3", "brdf_order4plus", "brdf_albedo"};
  if (m.substrate == 0)
    n.insert(n.end(), {"brdf_btdf", "brdf_btdf_order1_volume", "brdf_btdf_order2", "brdf_btdf_order4plus",
                       "brdf_btdf_albedo", "brdf_btdf_delta"});
  else if (m.substrate == 1)
    n.push_back("brdf_order1_substrate");
  else
    n.push_back("brdf_delta");  // the mirror lobe (order 1 on the substrate is all delta)
  return n;
}

constexpr double kAlpha = 0.01 / 166;
const char* const kEstimators[] = {"next_event", "next_event_mis"};
constexpr double kPaths = 10 * 20000;  // per incident direction

// The projected solid angle of cell i of an f table (theta_o, phi bins), 1 for energy tables.
double cell_measure(const Table& t, std::size_t i) {
  if (t.axes.size() != 5) return 1;
  const std::vector<std::size_t> shape = t.shape();
  const std::size_t p = i / 3 % shape[3], q = i / 3 / shape[3] % shape[2];
  const double mu_a = std::cos(t.axes[2].lower(q)), mu_b = std::cos(t.axes[2].upper(q));
  const double fold = t.axes[3].values.back() < 4 ? 2 : 1;  // folded azimuths cover [0, pi]
  return fold * 0.5 * std::fabs(mu_a * mu_a - mu_b * mu_b) * (t.axes[3].upper(p) - t.axes[3].lower(p));
}

void expect_consistent(const std::vector<Table>& analog, const std::vector<Table>& next_event,
                       const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    const Table &a = slab_test::find(analog, name), &b = slab_test::find(next_event, name);
    std::vector<double> diff(a.cells()), se(a.cells()), zero(a.cells(), 0.0);
    double unreached = 0;  // the largest N E of a cell the analog walk never reached
    for (std::size_t i = 0; i < a.cells(); ++i) {
      diff[i] = a.value(i) - b.value(i);
      se[i] = std::hypot(a.stderr_of(i), b.stderr_of(i));
      if (a.sum[i] == 0) {
        diff[i] = NAN;
        unreached = std::max(unreached, kPaths * b.value(i) * cell_measure(b, i));
      }
    }
    const Comparison c = compare(diff, se, zero, a.batches, {}, a.channels());
    const Verdict verdict = judge(c, true, kAlpha, 0);
    EXPECT_EQ(verdict.status, "pass") << name << ": " << verdict.reason;
    EXPECT_GT(c.cells, 0u) << name;
    EXPECT_LE(unreached, std::log(static_cast<double>(a.cells()) / kAlpha)) << name << ": a cell the analog walk never reached";
  }
}

class NextEventAgainstAnalog : public testing::TestWithParam<std::tuple<int, int>> {};

}  // namespace

TEST_P(NextEventAgainstAnalog, SameTablesWithinStatistics) {
  const auto [medium, estimator] = GetParam();
  const Medium& m = kMedia[medium];
  expect_consistent(slab_test::run(experiment(m, "analog", 51)), slab_test::run(experiment(m, kEstimators[estimator], 52)),
                    tables_of(m));
}

INSTANTIATE_TEST_SUITE_P(Media, NextEventAgainstAnalog, testing::Combine(testing::Range(0, 8), testing::Range(0, 2)));

// The paper's depth cap: an event past max_order is dropped before its escape is tallied.
TEST(NextEvent, OrderCapAgreesWithAnalog) {
  const std::string cap = "max_order = 2\n";
  const std::vector<Table> analog = slab_test::run(experiment(kMedia[2], "analog", 53, cap));
  for (const char* estimator : kEstimators)
    expect_consistent(analog, slab_test::run(experiment(kMedia[2], estimator, 54, cap)), {"brdf", "brdf_btdf"});
}

// exp(-sum over the layers crossed of rho sigma path length), to rounding.
TEST(NextEvent, EscapeProbabilityThroughLayers) {
  const std::string layers =
      "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 1.0\ndensity = 1.5\n"
      "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 2.0\ndensity = 0.5\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  const volume::SlabMedium open(parse_experiment("[geometry]\nkind = \"slab\"\n" + layers, "e.toml").slab);
  const volume::SlabMedium floor(
      parse_experiment("[geometry]\nkind = \"slab\"\nsubstrate = \"lambertian\"\n" + layers, "e.toml").slab);
  const Vec3 up{0.8, 0, 0.6}, down{0, -0.8, -0.6};
  EXPECT_NEAR(volume::escape_probability(open, 1, 1.8, up), std::exp(-(0.5 * 0.8 + 1.5 * 1.0) / 0.6), 1e-15);
  EXPECT_NEAR(volume::escape_probability(open, 1, 1.8, down), std::exp(-0.5 * 1.2 / 0.6), 1e-15);
  EXPECT_NEAR(volume::escape_probability(open, 0, 0.25, down), std::exp(-(1.5 * 0.75 + 0.5 * 2.0) / 0.6), 1e-15);
  EXPECT_EQ(volume::escape_probability(floor, 1, 1.8, down), 0.0);  // nothing leaves through a substrate
  EXPECT_NEAR(volume::escape_probability(floor, 1, 3.0, up), std::exp(-(0.5 * 2.0 + 1.5 * 1.0) / 0.6), 1e-15);
  EXPECT_EQ(volume::escape_probability(open, 0, 0.5, Vec3{1, 0, 0}), 0.0);  // along the horizon
}

// Through OpenVDB layers varying in depth only: exp(-sum over the layers crossed of
// sigma / |d.z| times the column of rho), in closed form for a linear profile
// (density 2 (0.5 + z) at depth z in the first layer: voxel values exact in
// float, and the trilinear field is that line) over a constant one.
TEST(NextEvent, EscapeProbabilityThroughDepthProfiles) {
  const std::string layers =
      "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 1.0\ndensity = 2.0\n"
      "profile = \"linear\"\nprofile_top = 0.5\nprofile_bottom = 1.5\n"
      "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 2.0\ndensity = 0.5\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  const volume::SlabMedium m(
      parse_experiment("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ndepth_voxels = 8\n" + layers, "e.toml").slab);
  ASSERT_EQ(volume::escape_unsupported(m), "");
  const Vec3 up{0.8, 0, 0.6}, down{0, -0.8, -0.6};
  // The first layer's column from depth a to b: 2 [0.5 z + z^2 / 2] from a to b.
  const auto column = [](double a, double b) { return 2 * ((0.5 * b + 0.5 * b * b) - (0.5 * a + 0.5 * a * a)); };
  EXPECT_NEAR(volume::escape_probability(m, 1, 1.8, up), std::exp(-(0.5 * 0.8 + column(0, 1)) / 0.6), 1e-14);
  EXPECT_NEAR(volume::escape_probability(m, 0, 0.25, down), std::exp(-(column(0.25, 1) + 0.5 * 2.0) / 0.6), 1e-14);
  EXPECT_NEAR(volume::escape_probability(m, 0, 0.25, up), std::exp(-column(0, 0.25) / 0.6), 1e-14);
  EXPECT_NEAR(volume::escape_probability(m, 0, 0.0, up), 1.0, 1e-15);  // on the top face
  EXPECT_EQ(volume::escape_probability(m, 0, 0.5, Vec3{1, 0, 0}), 0.0);  // along the horizon
}

// A layer whose density varies laterally has no column: the estimators refuse it,
// naming the layer (simulate_slab asks before any path; no TOML builds such a
// layer, so this test builds one by editing the grids), and escape_probability
// throws rather than return a wrong value.
TEST(NextEvent, RefusesLaterallyVaryingLayers) {
  const SlabGeometry g = slab_test::lateral_grid_experiment().slab;
  auto grids = std::make_unique<volume::DensityGrids>(g);
  for (auto it = grids->grids()[0]->beginValueOn(); it; ++it)
    it.setValue(*it * static_cast<float>(1 + 0.5 * std::cos(2 * kPi * it.getCoord().x() / g.grid.lateral_voxels)));
  const volume::SlabMedium m(g, std::move(grids));
  const std::string why = volume::escape_unsupported(m);
  EXPECT_NE(why.find("layer 0 varies laterally"), std::string::npos) << why;
  EXPECT_THROW(volume::escape_probability(m, 0, 0.5, Vec3{0, 0.6, 0.8}), std::invalid_argument);
}

// A conservative two-layer stack: R + T_scattered = 1 - T_delta within
// statistics (the energy table). R + T is no longer 1 path by path.
TEST(NextEvent, WhiteFurnace) {
  const Medium conservative{
      "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.3\noptical_thickness = 1.5\n"
      "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.6\norientation = [0, 1, 0.3]\noptical_thickness = 1.0\n",
      0};
  for (const char* estimator : kEstimators) {
    const Experiment ex = experiment(conservative, estimator, 55);
    slab_test::expect_exact(slab_test::run(ex), "brdf_energy", "white_furnace", ex);
  }
}

TEST(NextEvent, BitIdenticalForAnyThreadCount) {
  slab_test::expect_bit_identical_threads(experiment(kMedia[2], "next_event", 56));
  slab_test::expect_bit_identical_threads(experiment(kMedia[3], "next_event_mis", 57));
  slab_test::expect_bit_identical_threads(experiment(kMedia[7], "next_event_mis", 58));
}

// estimator = "next_event" takes the scalar walk, over homogeneous or OpenVDB
// layers (every TOML's OpenVDB layer varies in depth only); the wave walk and an
// unknown estimator are config errors naming the key and the file.
TEST(NextEvent, RejectsWhatItDoesNotCover) {
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\n";
  const std::string run = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  for (const std::string& geometry :
       {"[geometry]\nkind = \"slab\"\nestimator = \"next_event\"\nwalk = \"wave\"\n" + layer + run,
        "[geometry]\nkind = \"slab\"\nestimator = \"nee\"\n" + layer + run}) {
    try {
      parse_experiment(geometry, "bad.toml");
      ADD_FAILURE() << "accepted: " << geometry;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("geometry.estimator"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.toml"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(parse_experiment("[geometry]\nkind = \"slab\"\nestimator = \"next_event_mis\"\nbackend = \"openvdb\"\n" + layer + run,
                                   "good.toml"));
}
