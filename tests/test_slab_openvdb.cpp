// The OpenVDB backend (delta tracking through density grids) against the
// homogeneous fast path, and a depth profile against the single-scattering
// model at the same optical thickness (transport depends on optical depth only).
#include <cmath>

#include <openvdb/io/File.h>

#include "sim/volume/density_grid.h"
#include "tests/test_slab_helpers.h"

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

// Two independent simulations: their difference over the quadrature of both errors.
TEST(SlabOpenVdb, HomogeneousGridAgreesWithFastPath) {
  const Experiment h = parse_experiment(std::string("[geometry]\nkind = \"slab\"\n") + kLayer + kRun, "h.toml");
  const Experiment v = parse_experiment(
      std::string("[geometry]\nkind = \"slab\"\nbackend = \"openvdb\"\ndepth_voxels = 8\n") + kLayer + kRun, "v.toml",
      {"run.seed=22"});
  const std::vector<Table> th = slab_test::run(h), tv = slab_test::run(v);
  for (const char* name : {"brdf", "brdf_btdf", "brdf_albedo", "brdf_btdf_albedo"}) {
    const Table &a = slab_test::find(th, name), &b = slab_test::find(tv, name);
    std::vector<double> diff(a.cells()), se(a.cells()), zero(a.cells(), 0.0);
    for (std::size_t i = 0; i < a.cells(); ++i) {
      diff[i] = a.value(i) - b.value(i);
      se[i] = std::hypot(a.stderr_of(i), b.stderr_of(i));
      if (i % 3) diff[i] = NAN;  // grey: one channel
    }
    const Comparison c = compare(diff, se, zero, a.batches);
    const Verdict verdict = judge(c, true, 1e-3, 0);
    EXPECT_EQ(verdict.status, "pass") << name << ": " << verdict.reason;
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

// export-vdb's writer: the grids read back through OpenVDB with their values.
TEST(SlabOpenVdb, WrittenGridsReadBack) {
  const Experiment ex = parse_experiment(std::string("[geometry]\nkind = \"slab\"\n") + kLayer + kLayer + kRun, "w.toml");
  const volume::DensityGrids grids(ex.slab);
  const std::string path = ::testing::TempDir() + "slab_test.vdb";
  volume::write_vdb(path, grids);
  openvdb::io::File file(path);
  file.open();
  const openvdb::GridPtrVecPtr read = file.getGrids();
  file.close();
  ASSERT_EQ(read->size(), 2u);
  const auto g = openvdb::gridPtrCast<openvdb::FloatGrid>((*read)[1]);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->getName(), "layer1_density");
  EXPECT_FLOAT_EQ(g->tree().getValue(openvdb::Coord(1, 2, 3)), 2.0f);
  EXPECT_EQ(g->metaValue<std::string>("phase"), "sggx_surface");
}
