// The next-event estimators of the slab walk ([geometry] estimator = "next_event"
// and "next_event_mis", sim/slab/walk.h) against the analog one on the same medium: two independent
// simulations (seeds 51 and 52, 10 batches of 20 000 paths per incident
// direction, 4 incident directions), every cell of the BRDF and BTDF (total and
// per order), albedo and delta tables compared through the quadrature of both
// standard errors (RGB): p >= alpha and the Sidak |z| bound at alpha, with
// alpha = 0.01 / 204, 204 being the number of table comparisons below (each
// comparison is up to three checks at alpha, so a family-wise false-failure rate
// of at most 3 %). Cells the analog walk never reached
// (zero in every batch: no standard error) are left out of the chi^2 and
// checked one by one: weights never exceed 1, so N paths per direction reach
// a cell of energy E (the next-event value times the bin's projected solid
// angle) at least N E times in expectation, and none arrive with probability
// at most exp(-N E); the test asks N E <= ln(cells / alpha) in every such cell. Media: SGGX surface and fibre flakes,
// one and two layers, HG, isotropic and Lambert-sphere layers, every substrate, an
// OpenVDB stack of a linear and a tabulated depth profile (escapes through columns),
// and two OpenVDB stacks with laterally varying layers read from density_vdb files
// (escapes estimated by residual ratio tracking).
// Then the escape probability itself and its estimate through laterally varying
// layers, the white furnace, thread-count independence and the config checks.
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "sim/experiment/config_error.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/escape.h"
#include "sim/slab/slab_vdb.h"
#include "sim/slab/voxel_density.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

struct Medium {
  std::string geometry;  // [geometry] keys and layers
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
     "profile = \"table\"\nprofile_table = [1.0, 0.2, 1.5, 0.6, 1.0]\n", 0},
};

// An OpenVDB slab on a unit tile of 8 x 8 voxel columns and 8 voxel intervals
// per layer: `keys` more [geometry] keys, then the layers (each without its
// density keys) and their densities (density or optical_thickness, profile).
std::string lateral_slab(const std::string& keys, const std::vector<std::string>& layers,
                         const std::vector<std::string>& densities = {}) {
  std::string text = "backend = \"openvdb\"\nlateral_voxels = 8\ndepth_voxels = 8\n" + keys;
  for (std::size_t k = 0; k < layers.size(); ++k)
    text += "[[geometry.layer]]\n" + layers[k] + (k < densities.size() ? densities[k] : "");
  return text;
}

// The densities of lateral_slab(keys, layers, densities), each voxel (i, j, z) of
// layer k times modulation(k, i, j, z) (z = 0 on the layer's bottom face), written
// as a density_vdb file in the test's temporary folder; returns the [geometry]
// text that reads it.
std::string with_density_vdb(const std::string& name, const std::string& keys, const std::vector<std::string>& layers,
                             const std::vector<std::string>& densities,
                             const std::function<double(int, int, int, int)>& modulation) {
  const SlabGeometry g =
      parse_experiment("[geometry]\nkind = \"slab\"\n" + lateral_slab(keys, layers, densities) +
                           "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 1\n",
                       "source.toml")
          .slab;
  volume::DensityGrids grids(g);
  for (std::size_t k = 0; k < layers.size(); ++k)
    for (auto it = grids.grids()[k]->beginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      it.setValue(static_cast<float>(*it * modulation(static_cast<int>(k), c.x(), c.y(), c.z())));
    }
  const std::string path = ::testing::TempDir() + name;
  volume::write_vdb(path, grids);
  return lateral_slab(keys + "density_vdb = \"" + path + "\"\n", layers);
}

double wave(int i, double cycles) { return std::cos(2 * kPi * cycles * i / 8); }

// A tilted SGGX fibre layer whose density varies laterally (and in depth) over an
// HG layer varying in depth only; no substrate.
Medium lateral_fibre_over_hg() {
  return {with_density_vdb("lateral_fibre.vdb", "",
                           {"phase = \"sggx_fiber\"\nalpha = 0.4\norientation_deg = [50, 20]\nthickness = 0.5\n"
                            "albedo = [0.95, 0.8, 0.6]\n",
                            "phase = \"hg\"\ng = 0.5\nthickness = 1.0\nalbedo = 0.9\n"},
                           {"density = 3.0\n", "density = 1.0\nprofile = \"linear\"\nprofile_top = 0.5\nprofile_bottom = 1.5\n"},
                           [](int k, int i, int j, int z) { return k == 0 ? (1 + 0.6 * wave(i, 1) * wave(j, 1)) * (0.8 + 0.05 * z) : 1.0; }),
          0};
}

// Two laterally varying layers over a Lambertian substrate: an isotropic layer
// empty over voxel columns i = 3 to 5 (zero density for x in [3/8, 5/8]: the least
// density of every row of cells is 0, no control part), denser with depth, over
// an HG layer varying along y.
Medium empty_columns_over_lambertian() {
  return {with_density_vdb("empty_columns.vdb", "substrate = \"lambertian\"\nsubstrate_albedo = [0.8, 0.5, 0.3]\n",
                           {"phase = \"isotropic\"\nthickness = 0.6\nalbedo = 0.9\n",
                            "phase = \"hg\"\ng = -0.3\nthickness = 0.6\nalbedo = 0.8\n"},
                           {"density = 2.0\n", "density = 1.5\n"},
                           [](int k, int i, int j, int z) {
                             if (k == 1) return 1 + 0.5 * wave(j, 1);
                             return i % 8 >= 3 && i % 8 <= 5 ? 0.0 : (1 + 0.5 * wave(i, 1)) * (0.5 + 0.1 * z);
                           }),
          1};
}

const std::vector<Medium>& media() {
  static const std::vector<Medium> m = [] {
    std::vector<Medium> all(std::begin(kMedia), std::end(kMedia));
    all.push_back(lateral_fibre_over_hg());
    all.push_back(empty_columns_over_lambertian());
    return all;
  }();
  return m;
}

// The transport view of a medium (its geometry alone).
volume::SlabMedium slab_medium(const Medium& m) {
  return volume::SlabMedium(parse_experiment("[geometry]\nkind = \"slab\"\n" + m.geometry +
                                                 "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 1\n",
                                             "medium.toml")
                                .slab);
}

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

constexpr double kAlpha = 0.01 / 204;
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
  const Medium& m = media()[medium];
  expect_consistent(slab_test::run(experiment(m, "analog", 51)), slab_test::run(experiment(m, kEstimators[estimator], 52)),
                    tables_of(m));
}

INSTANTIATE_TEST_SUITE_P(Media, NextEventAgainstAnalog, testing::Combine(testing::Range(0, 10), testing::Range(0, 2)));

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

// Through laterally varying layers, escape_estimate against the transmittance
// from a quadrature of the optical depth along the ray (composite 3-point
// Gauss-Legendre on 4 000 intervals per layer, of the same trilinear field the
// flights read: its error is far below the tolerance). Per ray, 100 000
// estimates (seed 59): each in [0, 1], and their mean within 4 standard errors
// of the quadrature's value (two-sided p = 6.3e-5 per ray, 7 rays). exact
// escape_probability refuses such a ray; where the ray crosses only layers
// varying in depth only, the estimate is escape_probability, with no random
// number drawn.
TEST(NextEvent, EscapeEstimateThroughLaterallyVaryingLayers) {
  const volume::SlabMedium fibre = slab_medium(media()[8]), empty = slab_medium(media()[9]);
  const auto quadrature = [](const volume::SlabMedium& m, const volume::Photon& p, Vec3 d) {
    const double gx[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)}, gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    double tau = 0;
    const int step = d.z > 0 ? -1 : 1, end = d.z > 0 ? -1 : static_cast<int>(m.layers().size());
    for (int k = p.layer; k != end; k += step) {
      const volume::MediumLayer& l = m.layers()[k];
      const double from = k == p.layer ? p.depth : d.z > 0 ? l.bottom : l.top, to = d.z > 0 ? l.top : l.bottom;
      const double s0 = (p.depth - from) / d.z, s1 = (p.depth - to) / d.z, h = (s1 - s0) / 4000;
      double column = 0;
      for (int n = 0; n < 4000; ++n)
        for (int q = 0; q < 3; ++q) {
          const double s = s0 + h * (n + 0.5 + 0.5 * gx[q]);
          column += gw[q] * 0.5 * h * m.voxels()->density(k, p.x + d.x * s, p.y + d.y * s, p.depth - d.z * s);
        }
      tau += m.majorants()[k].factor(d) * column;
    }
    return std::exp(-tau);
  };
  struct Ray {
    const volume::SlabMedium* medium;
    int layer;
    double x, y, depth;
    Vec3 d;
  };
  const auto dir = [](double theta_deg, double phi_deg, bool up) {
    const double t = theta_deg * kPi / 180, f = phi_deg * kPi / 180;
    return Vec3{std::sin(t) * std::cos(f), std::sin(t) * std::sin(f), up ? std::cos(t) : -std::cos(t)};
  };
  const Ray rays[] = {
      {&fibre, 0, 0.13, 0.71, 0.3, dir(30, 20, true)},        // out of the lateral layer
      {&fibre, 0, 0.52, 0.05, 0.1, dir(25, 200, false)},      // through it, then the profile layer
      {&fibre, 1, 0.9, 0.4, 0.6, dir(60, 135, true)},         // the profile layer, then the lateral one
      {&fibre, 0, 0.3, 0.3, 0.05, dir(85, 300, true)},        // grazing, across 4-5 voxel columns
      {&fibre, 1, 0.7, 0.8, 1.4, dir(65, 30, true)},          // deep: the roulette (below kRouletteBelow) at work
      {&empty, 0, 0.45, 0.2, 0.4, dir(40, 10, true)},         // no control part (least density 0)
      {&empty, 1, 0.05, 0.9, 0.9, dir(60, 250, true)},        // through two laterally varying layers
  };
  Rng rng(59);
  for (const Ray& r : rays) {
    SCOPED_TRACE("ray " + std::to_string(&r - rays));
    volume::Photon p;
    p.layer = r.layer;
    p.x = r.x;
    p.y = r.y;
    p.depth = r.depth;
    const double exact = quadrature(*r.medium, p, r.d);
    ASSERT_GT(exact, 1e-3);  // not a comparison of zeros
    ASSERT_LT(exact, 0.98);
    constexpr int kN = 100000;
    double sum = 0, sum_sq = 0;
    for (int n = 0; n < kN; ++n) {
      const double e = volume::escape_estimate(*r.medium, p, r.d, rng);
      ASSERT_GE(e, 0.0);
      ASSERT_LE(e, 1.0);
      sum += e;
      sum_sq += e * e;
    }
    const double mean = sum / kN, se = std::sqrt((sum_sq / kN - mean * mean) / (kN - 1));
    EXPECT_LE(std::fabs(mean - exact), 4 * se) << "layer " << r.layer << " depth " << r.depth << ": estimate " << mean
                                                << " +- " << se << ", quadrature " << exact;
    EXPECT_THROW(volume::escape_probability(*r.medium, p.layer, p.depth, r.d), std::invalid_argument);
  }
  // Down through the profile layer only: escape_probability, and the stream untouched.
  volume::Photon p;
  p.layer = 1;
  p.x = 0.3;
  p.depth = 1.1;
  const Vec3 down = dir(30, 0, false);
  Rng a(60), b(60);
  EXPECT_EQ(volume::escape_estimate(fibre, p, down, a), volume::escape_probability(fibre, 1, 1.1, down));
  EXPECT_EQ(a.uniform(), b.uniform());
  EXPECT_EQ(volume::escape_estimate(empty, volume::Photon{}, down, a), 0.0);  // toward the substrate
}

// A ray almost parallel to the faces, along the empty stripe of media()[9]'s top
// layer (x = 0.5, in [3/8, 5/8]): every factor is 1, so only the cap of
// kMaxPoints ends the tracking (without it, about 1e300 lookups); the estimate is
// 1, the ray's transmittance.
TEST(NextEvent, EscapeEstimateEndsAlongAnEmptyStripe) {
  const volume::SlabMedium empty = slab_medium(media()[9]);
  ASSERT_EQ(empty.majorants()[0].row_lo[0], 0.0);
  volume::Photon p;
  p.x = 0.5;
  p.y = 0.3;
  p.depth = 0.3;
  Rng rng(63);
  EXPECT_EQ(volume::escape_estimate(empty, p, Vec3{0, 1, 1e-300}, rng), 1.0);
}

// A layer whose S varies (only C++ code builds one, by editing the grids) has no
// extinction rho(x) sigma(w): the estimators refuse it, naming the layer
// (simulate_slab asks before any path).
TEST(NextEvent, RefusesLayersWhoseSVaries) {
  const SlabGeometry g = slab_test::lateral_grid_experiment().slab;
  auto grids = std::make_unique<volume::DensityGrids>(g);
  grids->s_diag(0)->tree().setValueOn(openvdb::Coord(3, 4, 1), openvdb::Vec3d(0.5, 0.5, 1.0));
  const volume::SlabMedium m(g, std::move(grids));
  ASSERT_TRUE(m.majorants()[0].s_varies);
  const std::string why = volume::escape_unsupported(m);
  EXPECT_NE(why.find("layer 0's S varies"), std::string::npos) << why;
  Rng rng(1);
  EXPECT_THROW(volume::escape_estimate(m, volume::Photon{}, Vec3{0, 0.6, 0.8}, rng), std::invalid_argument);
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
  slab_test::expect_bit_identical_threads(experiment(media()[8], "next_event_mis", 61));
  slab_test::expect_bit_identical_threads(experiment(media()[9], "next_event", 62));
}

// The next-event estimators take either walk, over homogeneous or OpenVDB
// layers; an unknown estimator is a config error naming the key and the file.
TEST(NextEvent, RejectsWhatItDoesNotCover) {
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\n";
  const std::string run = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  try {
    parse_experiment("[geometry]\nkind = \"slab\"\nestimator = \"nee\"\n" + layer + run, "bad.toml");
    ADD_FAILURE() << "accepted estimator = \"nee\"";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry.estimator"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.toml"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(parse_experiment("[geometry]\nkind = \"slab\"\nestimator = \"next_event_mis\"\nbackend = \"openvdb\"\n" + layer + run,
                                   "good.toml"));
  for (const char* estimator : {"next_event", "next_event_mis"})
    EXPECT_NO_THROW(parse_experiment("[geometry]\nkind = \"slab\"\nwalk = \"wave\"\nestimator = \"" + std::string(estimator) +
                                         "\"\n" + layer + run,
                                     "good.toml"));
}
