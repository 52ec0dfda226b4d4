// The data-parallel slab walk (sim/slab/wave_walk.h) on OpenVDB slabs against
// the scalar walk (sim/slab/free_flight.cpp: exact flights through the TOML
// slabs' depth profiles, delta tracking through the laterally varying layer)
// on the same medium: two independent simulations, every cell of the BRDF, BTDF and
// per-component albedo and delta tables compared through the quadrature of both
// standard errors (RGB, each channel's chi2 on its own, Bonferroni over the
// three: a path's channels are one sample), p >= alpha and the Sidak |z| bound at alpha, with
// alpha = 0.01 / 57, 57 being the number of table comparisons below (a
// family-wise false-failure rate of 1 %).
//  - depth profiles (TOML): 10 batches of 20 000 paths at theta_i = 20, 70 deg
//    and phi_i = 0, 90 deg, 5 x 6 outgoing bins (seeds 71-78);
//  - a laterally varying layer (density times 1 + 0.9 cos(2 pi x) on a unit
//    tile of 16 x 16 voxel columns; no TOML reaches it), alone and with a
//    linear depth profile: 10 batches of 20 000 paths at theta_i = 30, 75 deg
//    and phi_i = 0, 90 deg (seeds 81-84), channel 0 only (a grey layer: the
//    other two are the same numbers). It fails with the cells' x and y swapped
//    (chi2/dof 5.6 to 63); on cos(2 pi x) cos(4 pi y), where the swap averages
//    out in these tables, it did not.
//  - the wave walk's exact flights through depth profiles against its own delta
//    tracking on the same medium (profiles not built): the first and third
//    slabs above, and a tabulated profile with a run of near-empty voxels
//    (whose thin intervals the stage's one step past the table's guess does not
//    cross: those flights are left to the scalar pass); the brdf tables of
//    lateral_tables below (all five without a substrate, else brdf and its
//    albedo; RGB for the first slab, else channel 0), seeds 87-92.
//  - the next-event estimators in both walks: next_event_mis on the four TOML
//    slabs above (seeds 93-100), and both estimators on the laterally varying
//    layer alone (its escapes estimated by residual ratio tracking, with the
//    lanes' draws; seeds 101-104).
// Then the white furnace, thread-count independence, what it rejects, and the
// flat tables of the cells' bounds it reads (sim/slab/cell_bounds.h).
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "models/core/rng.h"
#include "models/core/warp.h"
#include "sim/parallel/run_chunks.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/walk.h"
#include "sim/slab/wave_walk.h"
#include "sim/tally/brdf_batch.h"
#include "sim/tally/brdf_tally.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

constexpr double kAlpha = 0.01 / 57;

// OpenVDB slabs a TOML reaches: {keys before the layers, the layers}.
const char* const kProfiles[][2] = {
    // One SGGX surface-like layer, density 0.5 at the top to 1.5 at the bottom, on a Lambertian base.
    {"substrate = \"lambertian\"\nsubstrate_albedo = [0.8, 0.5, 0.3]\n",
     "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.4\noptical_thickness = 2.0\nprofile = \"linear\"\n"
     "profile_top = 0.5\nprofile_bottom = 1.5\nalbedo = [0.95, 0.8, 0.6]\nf0 = [1.0, 0.7, 0.4]\n"},
    // Henyey-Greenstein, a tabulated profile with a near-empty middle, nothing below (BTDF and its delta lobe).
    {"substrate = \"none\"\n",
     "[[geometry.layer]]\nphase = \"hg\"\ng = 0.7\noptical_thickness = 1.5\nprofile = \"table\"\n"
     "profile_table = [2.0, 0.05, 1.0, 3.0, 2.0]\nalbedo = [0.9, 0.7, 0.5]\n"},
    // Two SGGX layers (surface over fibre), each with its own profile, over a rough conductor.
    {"substrate = \"rough_conductor\"\nsubstrate_alpha = 0.3\n",
     "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.2\noptical_thickness = 0.8\nprofile = \"linear\"\n"
     "profile_top = 2.0\nprofile_bottom = 0.2\nalbedo = 0.9\nf0 = 0.6\n"
     "[[geometry.layer]]\nphase = \"sggx_fiber\"\nalpha = 0.5\norientation = [0, 1, 0.3]\noptical_thickness = 1.5\n"
     "albedo = 0.95\n"},
    // Lambert spheres on a constant grid, over a smooth conductor (its mirror lobe).
    {"substrate = \"conductor\"\n",
     "[[geometry.layer]]\nphase = \"lambert_sphere\"\noptical_thickness = 1.0\nalbedo = 0.9\n"},
};

Experiment profile_experiment(int k, const std::string& walk, int seed, const std::string& geometry_extra = "") {
  return slab_test::four_directions("walk = \"" + walk + "\"\nbackend = \"openvdb\"\ndepth_voxels = 8\n" + geometry_extra +
                                        kProfiles[k][0] + kProfiles[k][1],
                                    seed);
}

class WaveGridAgainstScalar : public testing::TestWithParam<int> {};

// A laterally varying layer (density times 1 + 0.9 cos(2 pi x) on a unit tile
// of 16 x 16 voxel columns), optionally with a linear depth profile.
SlabGeometry lateral_geometry(bool profile) {
  return slab_test::lateral_grid_experiment(std::string("albedo = [0.9, 0.8, 0.7]\n") +
                                            (profile ? "profile = \"linear\"\nprofile_top = 0.3\nprofile_bottom = 1.7\n" : ""))
      .slab;
}

std::unique_ptr<volume::SlabMedium> cosine_lateral_medium(const SlabGeometry& g) {
  auto grids = std::make_unique<volume::DensityGrids>(g);
  const int n = g.grid.lateral_voxels;
  for (auto it = grids->grids()[0]->beginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    it.setValue(*it * static_cast<float>(1 + 0.9 * std::cos(2 * kPi * c.x() / n)));
  }
  return std::make_unique<volume::SlabMedium>(g, std::move(grids));
}

BrdfLayout lateral_layout() {
  BrdfLayout layout;
  layout.theta_o_bins = 5;
  layout.phi_bins = 6;
  layout.transmission = true;
  layout.order1_classes = {"volume", "substrate"};
  return layout;
}

// One direction's sums over `paths` paths (run_chunks, as simulate_slab runs them).
std::vector<double> lateral_sums(const volume::SlabMedium& medium, const BrdfLayout& layout, bool wave, double theta_i,
                                 double phi_i, std::uint64_t paths, std::uint64_t seed,
                                 SlabEstimator estimator = SlabEstimator::kAnalog) {
  const Vec3 wi = spherical_direction(theta_i, phi_i);
  return run_chunks(paths, layout.sums_size(), seed, [&](Rng& rng, std::uint64_t count, Sums& s) {
    BrdfAccumulator acc(layout, phi_i, s);
    volume::WalkSettings ws;
    ws.estimator = estimator;
    if (wave) {
      volume::wave_walk(medium, ws, wi, count, rng, acc);
      return;
    }
    auto flight = volume::make_flight(medium);
    for (std::uint64_t n = 0; n < count; ++n) volume::walk(medium, *flight, ws, wi, rng, acc);
  });
}

// The brdf tables of 10 batches of 20 000 paths at theta_i = 30, 75 deg.
std::vector<Table> lateral_tables(const volume::SlabMedium& medium, bool wave, std::uint64_t seed,
                                  SlabEstimator estimator = SlabEstimator::kAnalog) {
  const BrdfLayout layout = lateral_layout();
  const std::vector<double> theta_i{30 * kPi / 180, 75 * kPi / 180}, phi_i{0, kPi / 2};
  std::vector<Table> tables = make_brdf_tables("brdf", theta_i, phi_i, layout);
  for (std::uint64_t b = 0; b < 10; ++b) {
    std::vector<std::vector<double>> sums;
    for (std::size_t i = 0; i < theta_i.size(); ++i)
      for (std::size_t j = 0; j < phi_i.size(); ++j)
        sums.push_back(lateral_sums(medium, layout, wave, theta_i[i], phi_i[j], 20000, stream_seed({seed, b, i, j}), estimator));
    add_brdf_batch(sums, 20000, layout, tables);
  }
  return tables;
}

const std::vector<std::string> kAllTables{"brdf", "brdf_albedo", "brdf_btdf", "brdf_btdf_albedo", "brdf_btdf_delta"};

}  // namespace

TEST_P(WaveGridAgainstScalar, SameTablesWithinStatistics) {
  const int k = GetParam();
  std::vector<std::string> names{"brdf", "brdf_albedo"};
  if (k == 1) names = kAllTables;
  if (k == 3) names.push_back("brdf_delta");
  slab_test::expect_same(slab_test::run(profile_experiment(k, "scalar", 71 + 2 * k)),
                         slab_test::run(profile_experiment(k, "wave", 72 + 2 * k)), names, false, kAlpha);
}

INSTANTIATE_TEST_SUITE_P(Profiles, WaveGridAgainstScalar, testing::Range(0, 4));

// The laterally varying layer, alone (the lateral cells) and with a depth
// profile (lateral and depth cells).
TEST(WaveGrid, LateralVariationAgreesWithScalar) {
  for (const bool profile : {false, true}) {
    const auto medium = cosine_lateral_medium(lateral_geometry(profile));
    ASSERT_GT(medium->majorants()[0].lateral, 1);
    ASSERT_EQ(medium->majorants()[0].depth_cells() > 1, profile);
    const std::uint64_t seed = profile ? 83 : 81;
    SCOPED_TRACE(profile ? "with a depth profile" : "lateral only");
    slab_test::expect_same(lateral_tables(*medium, false, seed), lateral_tables(*medium, true, seed + 1), kAllTables, true,
                           kAlpha);
  }
}

// The next-event estimators in both walks: on the TOML slabs (depth profiles
// flown exactly, the escapes in closed form), and through the laterally varying
// layer (escapes estimated with the lanes' draws).
TEST(WaveGrid, NextEventAgreesWithScalar) {
  const std::string mis = "estimator = \"next_event_mis\"\n";
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE("slab " + std::to_string(k));
    std::vector<std::string> names{"brdf", "brdf_albedo"};
    if (k == 1) names = kAllTables;
    if (k == 3) names.push_back("brdf_delta");
    slab_test::expect_same(slab_test::run(profile_experiment(k, "scalar", 93 + 2 * k, mis)),
                           slab_test::run(profile_experiment(k, "wave", 94 + 2 * k, mis)), names, false, kAlpha);
  }
  const auto medium = cosine_lateral_medium(lateral_geometry(false));
  for (const SlabEstimator estimator : {SlabEstimator::kNextEvent, SlabEstimator::kNextEventMis}) {
    const std::uint64_t seed = estimator == SlabEstimator::kNextEvent ? 101 : 103;
    SCOPED_TRACE(estimator == SlabEstimator::kNextEvent ? "lateral, next_event" : "lateral, next_event_mis");
    slab_test::expect_same(lateral_tables(*medium, false, seed, estimator), lateral_tables(*medium, true, seed + 1, estimator),
                           kAllTables, true, kAlpha);
  }
}

// Exact flights (sim/slab/depth_profile.h) against delta tracking, both in the wave walk.
TEST(WaveGrid, ExactFlightsAgreeWithDeltaTracking) {
  const std::string thin =
      "substrate = \"none\"\n[[geometry.layer]]\nphase = \"isotropic\"\noptical_thickness = 3.0\n"
      "profile = \"table\"\nprofile_table = [3.0, 0.002, 0.002, 0.002, 0.002, 0.002, 0.002, 0.002, 3.0]\nalbedo = 0.9\n";
  const std::string slabs[] = {std::string(kProfiles[0][0]) + kProfiles[0][1],
                               std::string(kProfiles[2][0]) + kProfiles[2][1], thin};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(slabs[k]);
    const SlabGeometry g =
        slab_test::four_directions("backend = \"openvdb\"\ndepth_voxels = 16\n" + slabs[k], 1).slab;
    const volume::SlabMedium exact(g, std::make_unique<volume::DensityGrids>(g));
    const volume::SlabMedium tracked(g, std::make_unique<volume::DensityGrids>(g), 0, 0, false);
    ASSERT_TRUE(exact.depth_profiles()[0].has_value());
    ASSERT_FALSE(tracked.depth_profiles()[0].has_value());
    const std::uint64_t seed = 87 + 2 * static_cast<std::uint64_t>(k);
    const std::vector<std::string> names = k < 2 ? std::vector<std::string>{"brdf", "brdf_albedo"} : kAllTables;
    slab_test::expect_same(lateral_tables(tracked, true, seed), lateral_tables(exact, true, seed + 1), names, k > 0,
                           kAlpha);
  }
}

// A conservative OpenVDB layer with a depth profile: R + T_scattered = 1 - T_delta
// within statistics, and R + T = 1 exactly with the delta lobe.
TEST(WaveGrid, WhiteFurnace) {
  const Experiment ex = slab_test::four_directions(
      "walk = \"wave\"\nbackend = \"openvdb\"\ndepth_voxels = 8\n[[geometry.layer]]\nphase = \"sggx_surface\"\n"
      "alpha = 0.3\noptical_thickness = 2.0\nprofile = \"linear\"\nprofile_top = 0.2\nprofile_bottom = 1.8\n",
      79);
  slab_test::expect_white_furnace(slab_test::run(ex), ex, 4);
}

// Bit-identical tables on 1 and 2 threads: a depth profile through simulate(),
// and the laterally varying layer (with a depth profile) through run_chunks
// (2^14 paths, theta_i = 50 deg, seed 11: 4 chunks), analog and with next_event_mis.
TEST(WaveGrid, BitIdenticalForAnyThreadCount) {
  slab_test::expect_bit_identical_threads(profile_experiment(0, "wave", 85));
  const auto medium = cosine_lateral_medium(lateral_geometry(true));
  const BrdfLayout layout = lateral_layout();
  for (const SlabEstimator estimator : {SlabEstimator::kAnalog, SlabEstimator::kNextEventMis}) {
    const auto sums = [&](int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      return lateral_sums(*medium, layout, true, 50 * kPi / 180, 0, 1 << 14, 11, estimator);
    };
    const std::vector<double> one = sums(1), two = sums(2);
    double energy = 0;
    for (const double v : one) energy += v;
    ASSERT_GT(energy, 0);  // not zero against zero
    EXPECT_EQ(one, two);
  }
}

// An SGGX matrix that varies over the layer (grids edited after they were
// built; no TOML makes one) is refused with a message, before any path.
TEST(WaveGrid, RefusesAVaryingSggxMatrix) {
  const SlabGeometry g = lateral_geometry(false);
  auto grids = std::make_unique<volume::DensityGrids>(g);
  grids->s_diag(0)->tree().setValueOn(openvdb::Coord(3, 4, 1), openvdb::Vec3d(0.5, 0.5, 1.0));
  const volume::SlabMedium medium(g, std::move(grids));
  ASSERT_TRUE(medium.majorants()[0].s_varies);
  BrdfLayout layout = lateral_layout();
  std::vector<double> sums(layout.sums_size(), 0.0);
  BrdfAccumulator acc(layout, 0.0, sums);
  Rng rng(1);
  try {
    volume::wave_walk(medium, volume::WalkSettings{}, spherical_direction(0.5, 0), 10, rng, acc);
    ADD_FAILURE() << "a varying S was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("SGGX matrix"), std::string::npos) << e.what();
  }
}

// The flat tables (sim/slab/cell_bounds.h) against the majorants they come
// from, on the laterally varying layer with a depth profile (4 depth cells of
// 32 x 32 lateral cells) over a homogeneous-looking second layer: every float
// bound on the outside of its double (lo below, hi above, by at most one float
// step), each voxel interval mapped to the depth cell that holds it, and
// rho_max the layer's largest hi.
TEST(CellBounds, FlatTablesKeepTheMajorantsBounds) {
  SlabGeometry g = lateral_geometry(true);
  g.layers.push_back(g.layers.front());
  g.layers.back().profile = DensityProfile{};
  const auto medium = cosine_lateral_medium(g);
  const volume::CellBounds& b = medium->cell_bounds();
  ASSERT_EQ(b.offset.size(), 2u);
  std::size_t cells = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    const volume::LayerMajorants& M = medium->majorants()[k];
    ASSERT_EQ(b.offset[k], cells);
    EXPECT_EQ(b.rho_max[k], *std::max_element(M.hi.begin(), M.hi.end()));
    for (std::size_t c = 0; c < M.hi.size(); ++c) {
      const float lo = b.lo[cells + c], hi = b.hi[cells + c];
      EXPECT_LE(lo, M.lo[c]);
      EXPECT_GT(std::nextafter(lo, INFINITY), M.lo[c]);
      EXPECT_GE(hi, M.hi[c]);
      EXPECT_LT(std::nextafter(hi, -INFINITY), M.hi[c]);
    }
    cells += M.hi.size();
    const int nz = g.grid.depth_voxels;
    const double top = M.faces.front(), hz = (M.faces.back() - top) / nz;
    for (int vz = 0; vz < nz; ++vz) {
      const int cell = b.depth_cell[b.depth_offset[k] + static_cast<std::size_t>(vz)];
      EXPECT_LE(M.faces[static_cast<std::size_t>(cell)], top + vz * hz + 1e-12) << k << " " << vz;
      EXPECT_GE(M.faces[static_cast<std::size_t>(cell) + 1], top + (vz + 1) * hz - 1e-12) << k << " " << vz;
    }
  }
  EXPECT_EQ(medium->majorants()[0].depth_cells(), 4);
  EXPECT_EQ(b.lo.size(), cells);
}
