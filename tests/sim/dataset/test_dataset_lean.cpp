// Lean storage (mcref dataset --lean, mcref merge --lean): value and stderr
// as float32 (the full file's values rounded to nearest), no sums, marked
// storage = "lean"; such a file cannot be merged nor become a resume's output
// (one line, exit 2, nothing written), while the full parts still resume into
// it, and shards merged --lean give the bytes of a direct lean run.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <fstream>

#include "sim/hdf5/h5_util.h"
#include "tests/sim/parallel/mpi_cli.h"

namespace fs = std::filesystem;
using namespace mcref_test;
namespace h5 = ::mcref::h5;

namespace {

// 8 x 32 x 32 directions a table: the table data outweigh the file's fixed overhead.
const char* kBase = R"(
[geometry]
kind = "slab"

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8

[run]
seed = 1
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [5, 15, 25, 35, 45, 55, 65, 75]
theta_o_bins = 32
phi_bins = 32
samples = 100
)";

const char* kDataset = R"(
[dataset]
experiment = "base.toml"
entries = 4
seed = 3

[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
)";

class DatasetLean : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mcref_test_dataset_lean_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml") << kBase;
    std::ofstream(dir_ / "ds.toml") << kDataset;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

struct H5File {
  explicit H5File(const fs::path& p) : id(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~H5File() {
    if (id >= 0) H5Fclose(id);
  }
  hid_t id;
};

}  // namespace

TEST_F(DatasetLean, Float32ValuesNoSumsAndAboutAQuarterOfTheSize) {
  std::string err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o full.h5 --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o lean.h5 --lean --quiet"), &err), 0) << err;
  // 8 bytes a cell (2 x float32) against 32 (4 x float64).
  const double ratio = static_cast<double>(fs::file_size(dir_ / "lean.h5")) / fs::file_size(dir_ / "full.h5");
  EXPECT_LT(ratio, 1.0 / 3) << ratio;
  EXPECT_GT(ratio, 1.0 / 4 - 0.01) << ratio;
  const H5File full(dir_ / "full.h5"), lean(dir_ / "lean.h5");
  ASSERT_GE(full.id, 0);
  ASSERT_GE(lean.id, 0);
  h5::Handle lean_root = h5::open_group(lean.id, "/");
  EXPECT_EQ(h5::read_string_attr(lean_root, "storage"), "lean");
  EXPECT_FALSE(h5::has_attr(h5::open_group(full.id, "/"), "storage"));
  for (int e = 0; e < 4; ++e) {
    const std::string g = "entries/" + std::to_string(e) + "/brdf";
    h5::Handle fg = h5::open_group(full.id, g), lg = h5::open_group(lean.id, g);
    EXPECT_EQ(h5::read_string_attr(lg, "storage"), "lean");
    EXPECT_FALSE(h5::exists(lg, "sum"));
    EXPECT_FALSE(h5::exists(lg, "sum_sq"));
    EXPECT_TRUE(h5::exists(fg, "sum"));
    for (const char* name : {"value", "stderr"}) {
      const std::vector<double> f = h5::read_doubles(fg, name), l = h5::read_doubles(lg, name);
      ASSERT_GE(f.size(), 8u * 32 * 32);
      ASSERT_EQ(l.size(), f.size());
      int differ = 0, nonzero = 0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        differ += !(l[i] == static_cast<double>(static_cast<float>(f[i])));
        nonzero += f[i] != 0;
      }
      EXPECT_EQ(differ, 0) << g << "/" << name;
      EXPECT_GT(nonzero, 0) << g << "/" << name;
    }
    h5::Handle value(H5Dopen2(lg, "value", H5P_DEFAULT), H5Dclose);
    h5::Handle type(H5Dget_type(value), H5Tclose);
    EXPECT_EQ(H5Tget_size(type), 4u);
  }
}

TEST_F(DatasetLean, LeanFilesAreNeitherMergedNorResumedInto) {
  std::string err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o lean.h5 --lean --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, "cp lean.h5 copy.h5", nullptr), 0);
  EXPECT_EQ(shell(dir_, mcref_test::mcref("merge lean.h5 -o m.h5 --quiet"), &err), 2);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(err.rfind("mcref: error: lean.h5: key 'storage': is a lean dataset", 0), 0u) << err;
  EXPECT_FALSE(fs::exists(dir_ / "m.h5"));
  // A full run onto the lean file: refused, the file untouched.
  EXPECT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o lean.h5 --quiet"), &err), 2);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("lean.h5: exists and one is lean storage, the other full"), std::string::npos) << err;
  EXPECT_EQ(shell(dir_, "cmp lean.h5 copy.h5", nullptr), 0);
  EXPECT_FALSE(fs::exists(dir_ / "lean.h5.parts"));
  // The same lean run again: up to date.
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o lean.h5 --lean"), &err), 0) << err;
  EXPECT_NE(err.find("up to date"), std::string::npos) << err;
}

TEST_F(DatasetLean, PartsResumeAndShardsMergeIntoTheSameLeanBytes) {
  std::string err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o lean.h5 --lean --quiet"), &err), 0) << err;
  // Interrupted, then resumed: the parts are full, the result lean.
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o r.h5 --lean --stop-after 2 --quiet"), &err), 0) << err;
  EXPECT_FALSE(fs::exists(dir_ / "r.h5"));
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o r.h5 --lean --quiet"), &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp lean.h5 r.h5", nullptr), 0);
  // Full shards merged --lean.
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o s0.h5 --shard 0/2 --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("dataset ds.toml -o s1.h5 --shard 1/2 --quiet"), &err), 0) << err;
  ASSERT_EQ(shell(dir_, mcref_test::mcref("merge s0.h5 s1.h5 -o m.h5 --lean --quiet"), &err), 0) << err;
  EXPECT_EQ(shell(dir_, "cmp lean.h5 m.h5", nullptr), 0);
}
