// mcref export-vdb for micrograin fields (sim/micrograin/micrograin_vdb.h): one
// realization voxelised, written, read back; its bottom voxel layer covers a
// fraction tau0 of the tile; the command writes the field simulate uses and
// refuses oversized grids.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <openvdb/io/File.h>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/micrograin/micrograin_vdb.h"

using namespace mcref;
namespace fs = std::filesystem;

namespace {

openvdb::FloatGrid::Ptr read_grains(const std::string& path) {
  openvdb::initialize();
  openvdb::io::File file(path);
  file.open();
  const openvdb::GridPtrVecPtr grids = file.getGrids();
  file.close();
  if (grids->size() != 1) return nullptr;
  return openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
}

double occupied_fraction(const openvdb::FloatGrid& g, int nx, int k) {
  auto acc = g.getConstAccessor();
  long long n = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nx; ++j) n += acc.getValue(openvdb::Coord(i, j, k)) > 0.5f;
  return static_cast<double>(n) / (static_cast<double>(nx) * nx);
}

// Boolean model of unit discs of radius a (the grains' cross-section at unit
// height z: a = sqrt(1 - z^2)), unit-space density lam = -ln(1 - tau0) / pi:
// coverage p = 1 - exp(-lam pi a^2) = 1 - (1 - tau0)^(a^2), and the covariance
// of the indicator at distance r is C(r) = (1 - p)^2 (exp(lam K(r)) - 1) with
// K the overlap area of two discs at distance r. The area fraction of one
// realization on a (periodic) tile of unit area A has variance
// (1/A) int C(r) 2 pi r dr (for A much larger than a disc).
struct Coverage {
  double p, sd;
};
Coverage boolean_coverage(double tau0, double z, double area) {
  const double lam = -std::log(1 - tau0) / kPi, a = std::sqrt(1 - z * z);
  const double p = 1 - std::exp(-lam * kPi * a * a);
  const int n = 4000;
  double integral = 0;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * 2 * a / n;
    const double overlap = 2 * a * a * std::acos(r / (2 * a)) - 0.5 * r * std::sqrt(4 * a * a - r * r);
    integral += (1 - p) * (1 - p) * (std::exp(lam * overlap) - 1) * 2 * kPi * r * (2 * a / n);
  }
  return {p, std::sqrt(integral / area)};
}

}  // namespace

// The bottom voxel layer: its occupied fraction is the realization's grain
// coverage at the height of its voxel centres, whose expectation is
// p = 1 - (1 - tau0)^(1 - z^2) (z = h_z / (2c), p = tau0 - 0.0014 here) and whose
// realization-to-realization standard deviation is the Boolean-model sd above
// (the voxel lattice samples one realization at ~200 points per grain area, so
// its own sampling error is small beside it). Tolerance: 4 sd.
TEST(ExportVdb, MicrograinBottomLayerCoversTau0) {
  MicrograinGeometry g;
  g.tau0 = 0.5;
  g.radius = 1.0;
  g.tile = 40;
  const std::uint64_t seed = micrograin_realization_seed(7, 0);
  const MicrograinField field(g, seed);
  const MicrograinVoxels v = micrograin_voxels(g, 0);
  EXPECT_EQ(v.nx, 320);
  EXPECT_EQ(v.nz, 8);
  const std::string path = ::testing::TempDir() + "grains_test.vdb";
  write_micrograin_vdb(path, micrograin_grid(field, v, 7, 0));
  const openvdb::FloatGrid::Ptr grid = read_grains(path);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->getName(), "grains");
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("tau0"), 0.5);
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("beta_x"), 1.0);
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("beta_y"), 1.0);
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("radius"), 1.0);
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("tile"), 40.0);
  EXPECT_EQ(grid->metaValue<openvdb::Int64>("grain_count"), static_cast<openvdb::Int64>(field.grain_count()));
  // Voxel (i, j, k) is centred at ((i + 1/2) h, (j + 1/2) h, (k + 1/2) h_z).
  const openvdb::Vec3d w = grid->transform().indexToWorld(openvdb::Coord(3, 4, 0));
  EXPECT_NEAR(w.x(), 3.5 * v.hx, 1e-12);
  EXPECT_NEAR(w.y(), 4.5 * v.hx, 1e-12);
  EXPECT_NEAR(w.z(), 0.5 * v.hz, 1e-12);

  const double z = 0.5 * v.hz / g.c();
  const Coverage cov = boolean_coverage(g.tau0, z, field.unit_side_x() * field.unit_side_y());
  const double f = occupied_fraction(*grid, v.nx, 0);
  EXPECT_NEAR(f, cov.p, 4 * cov.sd) << "tau0 = " << g.tau0 << ", sd = " << cov.sd;
  EXPECT_LT(cov.sd, 0.03);
  // Nothing above z = c, and fewer grains higher up.
  EXPECT_LT(occupied_fraction(*grid, v.nx, v.nz - 1), f);
  EXPECT_EQ(occupied_fraction(*grid, v.nx, v.nz), 0.0);

  // Every voxel agrees with the field's own inside test at its centre.
  auto acc = grid->getConstAccessor();
  Rng rng(3);
  for (int n = 0; n < 3000; ++n) {
    const int i = static_cast<int>(rng.uniform() * v.nx), j = static_cast<int>(rng.uniform() * v.nx),
              k = static_cast<int>(rng.uniform() * v.nz);
    const Vec3 p = field.to_unit({(i + 0.5) * v.hx, (j + 0.5) * v.hx, (k + 0.5) * v.hz});
    const bool inside = field.inside_other_grain(p, std::numeric_limits<std::size_t>::max());
    EXPECT_EQ(acc.getValue(openvdb::Coord(i, j, k)) > 0.5f, inside) << i << " " << j << " " << k;
  }
}

// Anisotropic grains (beta_x != beta_y): the same coverage law holds in unit space.
TEST(ExportVdb, AnisotropicMicrograinCoverage) {
  MicrograinGeometry g;
  g.tau0 = 0.3;
  g.beta_x = 0.6;
  g.beta_y = 1.2;
  g.radius = 1.0;
  g.tile = 40;
  const std::uint64_t seed = micrograin_realization_seed(11, 0);
  const MicrograinField field(g, seed);
  const MicrograinVoxels v = micrograin_voxels(g, 0.1);
  const openvdb::FloatGrid::Ptr grid = micrograin_grid(field, v, 11, 0);
  const double z = 0.5 * v.hz / g.c();
  const Coverage cov = boolean_coverage(g.tau0, z, field.unit_side_x() * field.unit_side_y());
  EXPECT_NEAR(occupied_fraction(*grid, v.nx, 0), cov.p, 4 * cov.sd);
}

TEST(ExportVdb, RefusesMoreThan2e8Voxels) {
  MicrograinGeometry g;
  g.tile = 1000;
  const MicrograinVoxels v = micrograin_voxels(g, 0.01);  // 1e5 x 1e5 x 100
  EXPECT_GT(v.count(), kMaxMicrograinVoxels);
}

// The command: realization 0 of run.seed, as simulate builds it; a clear refusal.
TEST(ExportVdb, CommandWritesSimulatedRealization) {
  const fs::path dir = fs::temp_directory_path() / ("mcref_test_export_vdb_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string toml = (dir / "field.toml").string(), out = (dir / "field.vdb").string(),
                    err = (dir / "err.txt").string();
  std::ofstream(toml) << "[geometry]\nkind = \"micrograin\"\ntau0 = 0.4\nbeta = 0.8\nradius = 1.0\ntile = 12\n"
                         "[run]\nseed = 9\nbatches = 2\n[[measure]]\nquantity = \"p1\"\nsamples = 100\n";
  auto run = [&](const std::string& args) {
    const std::string cmd = std::string("'") + MCREF_BINARY + "' export-vdb '" + toml + "' " + args + " 2> '" + err + "'";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  ASSERT_EQ(run("-o '" + out + "' --quiet"), 0);
  const openvdb::FloatGrid::Ptr grid = read_grains(out);
  ASSERT_TRUE(grid);
  MicrograinGeometry g;
  g.tau0 = 0.4;
  g.beta_x = g.beta_y = 0.8;
  g.radius = 1.0;
  g.tile = 12;
  const std::uint64_t seed = micrograin_realization_seed(9, 0);
  const MicrograinField field(g, seed);
  // run.seed and the realization: the field is built again from them (the
  // derived seed was written, negative as Int64 for half the seeds).
  EXPECT_EQ(grid->metaValue<openvdb::Int64>("seed"), 9);
  EXPECT_EQ(grid->metaValue<openvdb::Int64>("realization"), 0);
  const MicrograinField again(g, micrograin_realization_seed(grid->metaValue<openvdb::Int64>("seed"),
                                                             grid->metaValue<openvdb::Int64>("realization")));
  EXPECT_EQ(again.grain_count(), field.grain_count());
  EXPECT_EQ(grid->metaValue<openvdb::Int64>("grain_count"), static_cast<openvdb::Int64>(field.grain_count()));
  EXPECT_DOUBLE_EQ(grid->metaValue<double>("beta_x"), 0.8);

  // Too many voxels: non-zero exit, one line naming the limit, no output file.
  const std::string big = (dir / "big.vdb").string();
  EXPECT_NE(run("-o '" + big + "' --voxel-size 0.001"), 0);
  std::stringstream e;
  e << std::ifstream(err).rdbuf();
  const std::string msg = e.str();
  EXPECT_NE(msg.find("2e8"), std::string::npos) << msg;
  EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 1) << msg;
  EXPECT_FALSE(fs::exists(big));
  fs::remove_all(dir);
}
