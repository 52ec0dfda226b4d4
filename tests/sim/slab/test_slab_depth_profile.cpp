// Exact flights through OpenVDB layers whose density varies in depth only
// (sim/slab/depth_profile.h), checked against the voxels' own reconstruction
// (VoxelDensity::density, the function delta tracking reads):
//  - the column of rho that travel() covers, integrated from the voxels (exact
//    on each voxel interval, where the density is linear in depth), to 1e-12
//    of the layer's column;
//  - which layers get a profile;
//  - the depths of first collisions of flights from either face of a
//    two-layer stack (different profiles and SGGX matrices: the optical depth
//    carried across the face, each layer's sigma(w)), binned against
//    1 - exp(-tau(z)), tau(z) integrated from the voxels the same way:
//    chi-squared over 24 depth bins and the exits, 200 000 flights per case
//    (seeds 91-94), p >= 0.001 each; the same for delta tracking through the
//    same media (seeds 95-98), which layers whose S varies still use.
// The white furnace and the comparisons with the homogeneous walk and with the
// wave walk's delta tracking on the same media are in test_slab_openvdb.cpp and
// test_slab_wave_grid.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "models/core/rng.h"
#include "models/core/statistics.h"
#include "sim/experiment/experiment.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/voxel_density.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;
using namespace mcref::volume;

namespace {

constexpr int kVoxels = 16;  // depth voxels per layer

// Two SGGX layers with their own depth profiles: a table with a nearly empty
// voxel and one that ends at zero, over a linear one.
SlabGeometry two_layers() {
  return parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
lateral_voxels = 4
depth_voxels = 16
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.3
thickness = 0.7
optical_thickness = 1.2
profile = "table"
profile_table = [2.0, 0.02, 1.0, 3.0, 0.0]
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.5
orientation_deg = [60, 30]
thickness = 1.3
optical_thickness = 0.9
profile = "linear"
profile_top = 0.2
profile_bottom = 1.8
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)",
                          "profile.toml")
      .slab;
}

// The column of rho of layer k between two depths (a <= b): the voxels' density
// is linear in depth between voxel planes, so on each piece of [a, b] between
// them the integral is the length times the density at the middle.
double voxel_column(const SlabMedium& m, int k, double a, double b) {
  const double bottom = m.layers()[k].bottom, hz = (bottom - m.layers()[k].top) / kVoxels;
  double sum = 0;
  for (int j = 0; j < kVoxels; ++j) {  // voxel interval [bottom - (j + 1) hz, bottom - j hz]
    const double lo = std::max(a, bottom - (j + 1) * hz), hi = std::min(b, bottom - j * hz);
    if (hi > lo) sum += (hi - lo) * m.voxels()->density(k, 0.37, 0.81, 0.5 * (lo + hi));
  }
  return sum;
}

TEST(DepthProfile, TravelCoversTheVoxelsColumn) {
  const SlabMedium m(two_layers());
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE(m.depth_profiles()[k].has_value()) << "layer " << k;
    const DepthProfile& P = *m.depth_profiles()[k];
    const double top = m.layers()[k].top, bottom = m.layers()[k].bottom;
    const double voxel = (bottom - top) / kVoxels, whole = voxel_column(m, k, top, bottom);
    Rng rng(17 + k);
    for (int i = 0; i < 200; ++i) {
      const double d0 = i < 2 ? (i ? bottom : top) : top + rng.uniform() * (bottom - top);
      ASSERT_NEAR(P.density(d0), m.voxels()->density(k, rng.uniform(), rng.uniform(), d0), 1e-14) << d0;
      for (const bool down : {true, false}) {
        const double room = down ? voxel_column(m, k, d0, bottom) : voxel_column(m, k, top, d0);
        const double tol = 1e-12 * whole;
        // Inside the layer: the column from d0 to the depth reached is the amount.
        const double want = rng.uniform() * room;
        double amount = want;
        const double d1 = P.travel(d0, down, amount);
        EXPECT_EQ(amount, 0.0);
        EXPECT_TRUE(down ? d1 >= d0 && d1 <= bottom : d1 <= d0 && d1 >= top) << d0 << " -> " << d1;
        EXPECT_NEAR(down ? voxel_column(m, k, d0, d1) : voxel_column(m, k, d1, d0), want, tol)
            << "layer " << k << " from " << d0 << (down ? " down" : " up") << " to " << d1 << ", voxel " << voxel;
        // Past the face: the face, and what is left beyond it.
        double past = room + 0.25;
        EXPECT_EQ(P.travel(d0, down, past), down ? bottom : top);
        EXPECT_NEAR(past, 0.25, tol) << "layer " << k << " from " << d0;
      }
    }
  }
}

// A laterally varying layer has no profile; its flights stay delta tracking.
TEST(DepthProfile, OnlyLayersUniformAcross) {
  const SlabGeometry g = slab_test::lateral_grid_experiment().slab;
  auto grids = std::make_unique<DensityGrids>(g);
  {
    const SlabMedium uniform(g, std::make_unique<DensityGrids>(g));
    EXPECT_TRUE(uniform.depth_profiles()[0].has_value());
  }
  grids->grids()[0]->tree().setValue(openvdb::Coord(5, 7, 2), 4.0f);
  const SlabMedium varying(g, std::move(grids));
  EXPECT_FALSE(varying.depth_profiles()[0].has_value());
}

// First collisions of flights entering at the top (or the bottom) face against
// 1 - exp(-tau(z)), tau(z) = sum over layers of sigma_k(w) / |w_z| times the
// column of rho_k crossed (integrated from the voxels).
void expect_collision_depths(Vec3 d, bool exact, std::uint64_t seed) {
  const SlabGeometry g = two_layers();
  const SlabMedium m(g, std::make_unique<DensityGrids>(g), 0, 0, exact);
  ASSERT_EQ(m.depth_profiles()[0].has_value(), exact);
  const bool down = d.z < 0;
  const double depth = m.bottom(), rate = std::fabs(d.z);
  constexpr int kBins = 24, kFlights = 200000;
  // Optical depth from the entry face to z.
  const auto tau = [&](double z) {
    double t = 0;
    for (int k = 0; k < 2; ++k) {
      const double a = std::max(m.layers()[k].top, down ? 0.0 : z), b = std::min(m.layers()[k].bottom, down ? z : depth);
      if (b > a) t += m.majorants()[k].factor(d) / rate * voxel_column(m, k, a, b);
    }
    return t;
  };
  std::vector<double> edge(kBins + 1), expected(kBins + 1);
  for (int b = 0; b <= kBins; ++b) edge[b] = depth * b / kBins;
  for (int b = 0; b < kBins; ++b) {
    const double near = down ? edge[b] : edge[b + 1], far = down ? edge[b + 1] : edge[b];
    expected[b] = kFlights * (std::exp(-tau(near)) - std::exp(-tau(far)));
  }
  expected[kBins] = kFlights * std::exp(-tau(down ? depth : 0.0));  // through the stack
  std::vector<double> seen(kBins + 1, 0.0);
  const auto flight = make_flight(m);
  Rng rng(seed);
  for (int n = 0; n < kFlights; ++n) {
    Photon p;
    p.d = d;
    p.x = rng.uniform();
    p.y = rng.uniform();
    p.depth = down ? 0.0 : depth;
    p.layer = down ? 0 : 1;
    const Flight f = flight->fly(p, rng);
    ASSERT_NE(f, Flight::kLost);
    if (f != Flight::kCollision) {
      ASSERT_EQ(f, down ? Flight::kExitBottom : Flight::kExitTop);
      seen[kBins] += 1;
      continue;
    }
    ASSERT_TRUE(p.depth >= 0 && p.depth <= depth) << p.depth;
    seen[std::min(kBins - 1, static_cast<int>(p.depth / depth * kBins))] += 1;
  }
  double chi2 = 0;
  for (int b = 0; b <= kBins; ++b) {
    ASSERT_GT(expected[b], 20) << "bin " << b;
    chi2 += (seen[b] - expected[b]) * (seen[b] - expected[b]) / expected[b];
  }
  const double p = chi2_survival(chi2, kBins);  // kBins + 1 cells, their sum fixed
  EXPECT_GE(p, 1e-3) << (exact ? "exact" : "delta tracking") << ": chi2 " << chi2 << " over " << kBins
                     << " dof; direction " << d.x << ", " << d.y << ", " << d.z;
}

// Exact flights, and delta tracking against the depth cells' majorants (the
// flights of layers whose S varies) on the same media.
TEST(DepthProfileFlight, CollisionDepthsFollowTheOpticalDepth) {
  const double th[2] = {0.35, 1.2}, ph[2] = {0.3, 2.1};
  for (const bool exact : {true, false})
    for (int i = 0; i < 2; ++i)
      for (const double sign : {-1.0, 1.0}) {
        const Vec3 d{std::sin(th[i]) * std::cos(ph[i]), std::sin(th[i]) * std::sin(ph[i]), sign * std::cos(th[i])};
        expect_collision_depths(d, exact, 91 + 4 * !exact + 2 * i + (sign > 0));
      }
}

}  // namespace
