// The OpenVDB backend (density and SGGX matrix grids; these layers vary in depth
// at most, so their flights invert the optical depth: sim/slab/depth_profile.h)
// against the homogeneous fast path, and a depth profile against the
// single-scattering model at the same optical thickness (transport depends on
// optical depth only).
#include <algorithm>
#include <cmath>
#include <map>

#include <openvdb/io/File.h>

#include "models/core/rng.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/slab_vdb.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {
const char* kLayer = R"(
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 2.0
albedo = 0.9
)";
const char* kRun = R"(
[run]
seed = 21
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [15, 60]
theta_o_bins = 6
phi_bins = 6
samples = 30000
)";
}  // namespace

namespace {
void expect_same(const Experiment& h, const Experiment& v) {
  slab_test::expect_same(slab_test::run(h), slab_test::run(v), {"brdf", "brdf_btdf", "brdf_albedo", "brdf_btdf_albedo"},
                         true);
}

// A tilted fibre layer (all six components of S non-zero, anisotropic medium)
// over a tilted surface layer.
const char* kTiltedLayers = R"(
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.3
orientation_deg = [60, 30]
thickness = 0.5
density = 3.0
albedo = 0.95
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.2
orientation_deg = [20, 110]
thickness = 1.0
density = 1.5
albedo = 0.8
)";
const char* kRunAniso = R"(
[run]
seed = 31
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
phi_i_deg = [0, 90]
theta_o_bins = 5
phi_bins = 8
samples = 30000
)";

sggx::Mat3 layer_s(const SlabLayer& l) {
  return (l.phase == SlabPhase::kSggxSurface ? sggx::surface_like(l.alpha, l.orientation)
                                             : sggx::fiber_like(l.alpha, l.orientation)).S;
}
}  // namespace

// The grid path reads density and S from the grids at every tentative
// collision and scattering event, against the majorant rho_max sqrt(lambda_max(S)).
TEST(SlabOpenVdb, HomogeneousGridAgreesWithFastPath) {
  const Experiment h = parse_experiment(std::string("[geometry]\nkind = \"slab\"\n") + kLayer + kRun, "h.toml");
  const Experiment v = parse_experiment(
      std::string("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ndepth_voxels = 8\n") + kLayer + kRun, "v.toml",
      {"run.seed=22"});
  expect_same(h, v);
}

// Constant alpha per layer, S from the grids against the layers' constant S,
// with every component of S non-zero.
TEST(SlabOpenVdb, TiltedSggxGridAgreesWithFastPath) {
  const Experiment h = parse_experiment(std::string("[geometry]\nkind = \"slab\"\n") + kTiltedLayers + kRunAniso, "h.toml");
  const Experiment v = parse_experiment(
      std::string("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ndepth_voxels = 4\nlateral_voxels = 3\n") +
          kTiltedLayers + kRunAniso,
      "v.toml", {"run.seed=32"});
  ASSERT_FALSE(h.isotropic);
  expect_same(h, v);
}

// S read back through the lookups (trilinear, periodic wrap, any point of the
// layer) equals the layer's S; the majorant factor is sqrt(lambda_max(S)) = max(1, alpha).
TEST(SlabOpenVdb, SggxMatrixReadBackEqualsLayerS) {
  const Experiment ex = parse_experiment(std::string("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\nlateral_voxels = 3\n") +
                                             kTiltedLayers + "[[geometry.layer]]\nphase = \"isotropic\"\n" + kRunAniso,
                                         "s.toml");
  const volume::DensityGrids grids(ex.slab);
  ASSERT_TRUE(grids.has_sggx(0) && grids.has_sggx(1));
  EXPECT_FALSE(grids.has_sggx(2));
  EXPECT_EQ(grids.max_sigma(2), 1.0);
  volume::GridLookup lookup(grids);
  Rng rng(5);
  double top = 0;
  for (int k = 0; k < 2; ++k) {
    const SlabLayer& l = ex.slab.layers[k];
    const sggx::Mat3 S = layer_s(l);
    EXPECT_NEAR(grids.max_sigma(k), std::max(1.0, l.alpha), 1e-9);
    EXPECT_NEAR(volume::largest_eigenvalue(S), std::max(1.0, l.alpha * l.alpha), 1e-12);
    for (int n = 0; n < 200; ++n) {
      const double x = (rng.uniform() - 0.5) * 10, y = (rng.uniform() - 0.5) * 10, depth = top + rng.uniform() * l.thickness;
      sggx::Mat3 s2;
      const double rho = lookup.density_and_sggx(k, x, y, depth, s2);
      EXPECT_NEAR(rho, l.density, 1e-6 * l.density);
      EXPECT_LT(sggx::max_abs_difference(lookup.sggx_matrix(k, x, y, depth), S), 1e-14);
      EXPECT_LT(sggx::max_abs_difference(s2, S), 1e-14);
    }
    // Every stored voxel holds the layer's S exactly.
    std::size_t voxels = 0;
    for (auto it = grids.s_diag(k)->cbeginValueOn(); it; ++it, ++voxels)
      EXPECT_EQ(*it, openvdb::Vec3d(S(0, 0), S(1, 1), S(2, 2)));
    for (auto it = grids.s_offdiag(k)->cbeginValueOn(); it; ++it)
      EXPECT_EQ(*it, openvdb::Vec3d(S(0, 1), S(0, 2), S(1, 2)));
    EXPECT_EQ(voxels, 4u * 4u * 33u);
    top += l.thickness;
  }
}

TEST(SlabOpenVdb, LinearProfileMatchesSingleScatteringAtSameOpticalThickness) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
depth_voxels = 10
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.4
orientation = [0, 0, 1]
thickness = 2.0
density = 1.0
profile = "linear"
profile_top = 0.2
profile_bottom = 1.0
albedo = 0.8
)" + std::string(kRun), "p.toml");
  volume::DensityGrids grids(ex.slab);
  EXPECT_NEAR(grids.column_optical_thickness(0), ex.slab.layers[0].optical_thickness(), 1e-6);
  const std::vector<Table> t = slab_test::run(ex);
  slab_test::expect_exact(t, "brdf_order1_volume", "spongecake_ss_brdf", ex);
  slab_test::expect_exact(t, "brdf_btdf_order1_volume", "spongecake_ss_btdf", ex);
}

// export-vdb's writer: the grids read back through OpenVDB with the values of
// the simulation's grids (per SGGX layer: density, S_diag, S_offdiag), as
// FloatGrid and Vec3SGrid (the types pyopenvdb reads), with the periodic seam
// once: N x N voxels laterally, not N + 1.
TEST(SlabOpenVdb, WrittenGridsReadBack) {
  const Experiment ex = parse_experiment(std::string("[geometry]\nkind = \"slab\"\n") + kLayer + kTiltedLayers + kRun, "w.toml");
  const volume::DensityGrids grids(ex.slab);
  const int n = ex.slab.grid.lateral_voxels, nz = ex.slab.grid.depth_voxels;
  const std::string path = ::testing::TempDir() + "slab_test.vdb";
  volume::write_vdb(path, grids);
  openvdb::io::File file(path);
  file.open();
  const openvdb::GridPtrVecPtr read = file.getGrids();
  file.close();
  ASSERT_EQ(read->size(), 9u);
  std::map<std::string, openvdb::GridBase::Ptr> by_name;
  for (const auto& g : *read) {
    by_name[g->getName()] = g;
    EXPECT_EQ(g->evalActiveVoxelBoundingBox(), openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(n - 1, n - 1, nz)))
        << g->getName();
  }
  const auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(by_name["layer1_density"]);
  ASSERT_TRUE(g);
  EXPECT_FLOAT_EQ(g->tree().getValue(openvdb::Coord(1, 2, 3)), 3.0f);
  EXPECT_EQ(g->metaValue<std::string>("phase"), "sggx_fiber");
  // The S grids of the tilted fibre layer hold its S, rounded to float.
  const sggx::Mat3 S = layer_s(ex.slab.layers[1]);
  const auto d = openvdb::gridPtrCast<openvdb::Vec3SGrid>(by_name["layer1_S_diag"]);
  const auto o = openvdb::gridPtrCast<openvdb::Vec3SGrid>(by_name["layer1_S_offdiag"]);
  ASSERT_TRUE(d && o);
  auto in_diag = grids.s_diag(1)->getConstAccessor();
  for (const openvdb::Coord c : {openvdb::Coord(2, 0, 5), openvdb::Coord(n - 1, n - 1, nz)}) {
    EXPECT_EQ(d->tree().getValue(c), openvdb::Vec3s(S(0, 0), S(1, 1), S(2, 2)));
    EXPECT_EQ(o->tree().getValue(c), openvdb::Vec3s(S(0, 1), S(0, 2), S(1, 2)));
    EXPECT_EQ(d->tree().getValue(c), openvdb::Vec3s(in_diag.getValue(c)));
  }
  EXPECT_EQ(d->metaValue<std::string>("components"), "S_xx S_yy S_zz");
  EXPECT_EQ(o->metaValue<std::string>("components"), "S_xy S_xz S_yz");
  EXPECT_DOUBLE_EQ(d->metaValue<double>("alpha"), 0.3);
  EXPECT_EQ(d->transform(), grids.s_diag(1)->transform());
}
