// sim/tally/table and sim/hdf5/table_file: HDF5 round trip, errors that name
// the file, atomic writes, exact merging, the stderr formula; the azimuth
// bins of the BRDF tally.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/experiment/config_error.h"
#include "sim/hdf5/h5_util.h"
#include "sim/hdf5/table_file.h"
#include "sim/tally/azimuth_bins.h"
#include "sim/tally/table.h"

using namespace mcref;
namespace fs = std::filesystem;

namespace {

// A fresh scratch directory per test, removed afterwards.
class TableFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mcref_test_table_file_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Names in the scratch directory (to catch stray temporaries).
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }
  fs::path dir_;
};

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Expects `fn` to throw ConfigError whose message names `file`; returns the message.
template <class F>
std::string expect_config_error(F&& fn, const std::string& file) {
  try {
    fn();
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file), std::string::npos) << "message does not name the file: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-ConfigError: " << e.what();
    return "";
  }
  ADD_FAILURE() << "did not throw";
  return "";
}

// A table with random per-batch estimates (seeded).
Table random_table(const std::string& name, std::vector<Axis> axes, int batches, std::uint64_t seed) {
  Table t(name, "test_quantity_" + name, std::move(axes));
  t.units = "1/sr";
  t.description = "a test table: " + name;
  Rng rng(seed);
  for (int b = 0; b < batches; ++b) {
    std::vector<double> est(t.cells());
    for (double& x : est) x = rng.uniform() * 3 - 1;
    t.add_batch(est);
  }
  return t;
}

TableFile sample_file() {
  TableFile f;
  f.provenance.mcref_version = "9.8.7";
  f.provenance.git_commit = "0123456789ab";
  f.provenance.sim_fingerprint = "00112233aabbccdd";
  f.provenance.created = "2024-01-02T03:04:05Z";
  f.provenance.command_line = "mcref simulate exp.toml -o out.h5 --set geometry.tau0=0.3";
  f.provenance.config = "[geometry]\nkind = \"micrograin\"\ntau0 = 0.5 # τ0, unicode\n";
  f.provenance.source_file = "validate/experiments/quick.toml";
  f.provenance.seed = 0xFEDCBA9876543210ull;  // above INT64_MAX: must survive the int64 attribute
  f.tables.push_back(random_table("vndf", {Axis::points("theta_i", "rad", {0.1, 0.7}),
                                           Axis::uniform_bins("theta_m", "rad", 0, kPi / 2, 5),
                                           Axis::bins("phi_m_rel", "rad", {0, 0.5, 1.5, kPi})},
                                  7, 1));
  f.tables.back().attributes["phi_m_rel"] = "phi_m - phi_i folded into [0, pi]";
  f.tables.back().attributes["empty_cells"] = "NaN where a batch had no sample";
  f.tables.push_back(random_table("p1", {Axis::uniform_bins("r", "grain radius", 0, 3, 12)}, 3, 2));
  f.tables.push_back(random_table("tau_plus", {Axis::points("theta_i", "rad", {0, 0.5, 1.2}),
                                               Axis::points("phi_i", "rad", {0})},
                                  1, 3));  // one batch: stderr NaN
  f.tables.push_back(random_table("empty", {Axis::points("h", "grain height c", {0, 0.5})}, 0, 4));
  return f;
}

void expect_same_table(const Table& a, const Table& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.quantity, b.quantity) << a.name;
  EXPECT_EQ(a.units, b.units) << a.name;
  EXPECT_EQ(a.description, b.description) << a.name;
  ASSERT_EQ(a.axes.size(), b.axes.size()) << a.name;
  for (std::size_t d = 0; d < a.axes.size(); ++d) {
    EXPECT_TRUE(a.axes[d] == b.axes[d]) << a.name << " axis " << a.axes[d].name;
    EXPECT_EQ(a.axes[d].kind, b.axes[d].kind) << a.name << " axis " << a.axes[d].name;
  }
  EXPECT_EQ(a.batches, b.batches) << a.name;
  EXPECT_EQ(a.sum, b.sum) << a.name;  // bit-exact
  EXPECT_EQ(a.sum_sq, b.sum_sq) << a.name;
  EXPECT_EQ(a.attributes, b.attributes) << a.name;
}

// Reads an N-d float64 dataset with the HDF5 C API.
std::vector<double> read_doubles(hid_t loc, const std::string& name) {
  const hid_t ds = H5Dopen2(loc, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << name;
  if (ds < 0) return {};
  const hid_t sp = H5Dget_space(ds);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(ds);
  return v;
}

bool same_or_both_nan(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

}  // namespace

TEST_F(TableFileTest, RoundTripKeepsTablesAxesAttributesAndProvenance) {
  const TableFile f = sample_file();
  const std::string p = path("tables.h5");
  write_table_file(p, f);
  EXPECT_EQ(entries(), std::vector<std::string>{"tables.h5"});  // no temporary left
  const TableFile r = read_table_file(p);
  EXPECT_EQ(r.provenance.mcref_version, f.provenance.mcref_version);
  EXPECT_EQ(r.provenance.git_commit, f.provenance.git_commit);
  EXPECT_EQ(r.provenance.sim_fingerprint, f.provenance.sim_fingerprint);
  EXPECT_EQ(r.provenance.created, f.provenance.created);
  EXPECT_EQ(r.provenance.command_line, f.provenance.command_line);
  EXPECT_EQ(r.provenance.config, f.provenance.config);
  EXPECT_EQ(r.provenance.source_file, f.provenance.source_file);
  EXPECT_EQ(r.provenance.seed, f.provenance.seed);
  ASSERT_EQ(r.tables.size(), f.tables.size());
  for (const Table& t : f.tables) {
    const Table* back = r.find(t.name);
    ASSERT_NE(back, nullptr) << t.name;
    expect_same_table(t, *back);
    for (std::size_t i = 0; i < t.cells(); ++i) {
      EXPECT_TRUE(same_or_both_nan(back->value(i), t.value(i))) << t.name << " cell " << i;
      EXPECT_TRUE(same_or_both_nan(back->stderr_of(i), t.stderr_of(i))) << t.name << " cell " << i;
    }
  }
}

// The on-disk layout DESIGN.md promises, checked with the bare HDF5 C API.
TEST_F(TableFileTest, LayoutHasValueStderrScalesBoundsAndRootAttributes) {
  const TableFile f = sample_file();
  const std::string p = path("layout.h5");
  write_table_file(p, f);
  const hid_t file = H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* a : {"mcref_format", "format_version", "mcref_version", "git_commit", "sim_fingerprint", "created", "command_line",
                        "seed", "config", "source_file", "conventions"})
    EXPECT_GT(H5Aexists(file, a), 0) << "root attribute " << a;
  const Table& t = f.tables[0];  // vndf: points x bins x bins
  const hid_t g = H5Gopen2(file, t.name.c_str(), H5P_DEFAULT);
  ASSERT_GE(g, 0);
  for (const char* a : {"quantity", "units", "description", "batches", "axes", "phi_m_rel", "empty_cells"})
    EXPECT_GT(H5Aexists(g, a), 0) << "table attribute " << a;
  const std::vector<double> value = read_doubles(g, "value"), err = read_doubles(g, "stderr");
  ASSERT_EQ(value.size(), t.cells());
  ASSERT_EQ(err.size(), t.cells());
  for (std::size_t i = 0; i < t.cells(); ++i) {
    EXPECT_EQ(value[i], t.value(i));
    EXPECT_EQ(err[i], t.stderr_of(i));
  }
  // Dimensions: value is theta_i x theta_m x phi_m_rel.
  const hid_t ds = H5Dopen2(g, "value", H5P_DEFAULT);
  const hid_t sp = H5Dget_space(ds);
  hsize_t dims[3] = {0, 0, 0};
  ASSERT_EQ(H5Sget_simple_extent_ndims(sp), 3);
  H5Sget_simple_extent_dims(sp, dims, nullptr);
  EXPECT_EQ(dims[0], 2u);
  EXPECT_EQ(dims[1], 5u);
  EXPECT_EQ(dims[2], 3u);
  for (unsigned d = 0; d < 3; ++d) {
    const hid_t scale = H5Dopen2(g, t.axes[d].name.c_str(), H5P_DEFAULT);
    ASSERT_GE(scale, 0) << t.axes[d].name;
    EXPECT_GT(H5DSis_scale(scale), 0) << t.axes[d].name;
    EXPECT_GT(H5DSis_attached(ds, scale, d), 0) << t.axes[d].name;
    const std::vector<double> pts = read_doubles(g, t.axes[d].name);
    ASSERT_EQ(pts.size(), t.axes[d].size());
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_DOUBLE_EQ(pts[i], t.axes[d].centre(i));
    // CF: units on the axis; bounds = "<axis>_bounds", an (n, 2) array, on binned axes.
    EXPECT_EQ(h5::read_string_attr(scale, "units"), t.axes[d].unit);
    const std::string bounds = t.axes[d].name + "_bounds";
    if (t.axes[d].kind == Axis::Kind::Bins) {
      EXPECT_EQ(h5::read_string_attr(scale, "bounds"), bounds);
      const std::vector<double> b = read_doubles(g, bounds);
      ASSERT_EQ(b.size(), 2 * t.axes[d].size()) << bounds;
      for (std::size_t i = 0; i < t.axes[d].size(); ++i) {
        EXPECT_EQ(b[2 * i], t.axes[d].values[i]) << bounds;
        EXPECT_EQ(b[2 * i + 1], t.axes[d].values[i + 1]) << bounds;
      }
    } else {
      EXPECT_FALSE(h5::has_attr(scale, "bounds")) << t.axes[d].name;
      EXPECT_LE(H5Lexists(g, bounds.c_str(), H5P_DEFAULT), 0) << bounds << " on a points axis";
    }
    H5Dclose(scale);
  }
  EXPECT_EQ(h5::read_string_attr(ds, "units"), t.units);
  H5Sclose(sp);
  H5Dclose(ds);
  H5Gclose(g);
  H5Fclose(file);
}

TEST_F(TableFileTest, MissingFileThrowsConfigErrorNamingIt) {
  const std::string p = path("does_not_exist.h5");
  expect_config_error([&] { read_table_file(p); }, p);
}

TEST_F(TableFileTest, NonHdf5FileThrowsConfigErrorNamingIt) {
  const std::string p = path("plain.txt");
  std::ofstream(p) << "this is not an HDF5 file\n";
  expect_config_error([&] { read_table_file(p); }, p);
  const std::string empty = path("empty.h5");
  std::ofstream(empty).close();
  expect_config_error([&] { read_table_file(empty); }, empty);
}

TEST_F(TableFileTest, Hdf5FileWithoutFormatAttributeThrowsConfigErrorNamingIt) {
  const std::string p = path("foreign.h5");
  {
    const hid_t file = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hid_t g = H5Gcreate2(file, "some_group", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 3;
    const double data[3] = {1, 2, 3};
    H5LTmake_dataset_double(g, "x", 1, &n, data);
    H5Gclose(g);
    H5Fclose(file);
  }
  const std::string msg = expect_config_error([&] { read_table_file(p); }, p);
  EXPECT_NE(msg.find("mcref_format"), std::string::npos) << msg;
}

// A directory given as a table file is not a table file either.
TEST_F(TableFileTest, DirectoryThrowsConfigErrorNamingIt) {
  const std::string p = path("a_directory");
  fs::create_directory(p);
  expect_config_error([&] { read_table_file(p); }, p);
}

TEST_F(TableFileTest, WriteIntoMissingDirectoryThrowsAndLeavesNothing) {
  const std::string p = path("no/such/dir/out.h5");
  expect_config_error([&] { write_table_file(p, sample_file()); }, p);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(entries().empty()) << "the scratch directory holds " << entries().size() << " entries";
}

// A write that fails after the temporary file exists (two tables with the
// same group name) throws and leaves neither the file nor a *.tmp.* file.
TEST_F(TableFileTest, FailedWriteLeavesNoFileAndNoTemporary) {
  TableFile bad = sample_file();
  bad.tables.push_back(bad.tables[1]);  // duplicate group "p1"
  const std::string p = path("out.h5");
  EXPECT_ANY_THROW(write_table_file(p, bad));
  EXPECT_FALSE(fs::exists(p));
  for (const std::string& e : entries()) ADD_FAILURE() << "left behind: " << e;
}

// A failing write over an existing good file leaves the good file byte-identical.
TEST_F(TableFileTest, FailedWriteOverGoodFileKeepsIt) {
  const std::string p = path("good.h5");
  write_table_file(p, sample_file());
  const std::string before = slurp(p);
  ASSERT_FALSE(before.empty());
  TableFile bad = sample_file();
  bad.tables.push_back(bad.tables[0]);  // duplicate group "vndf"
  EXPECT_ANY_THROW(write_table_file(p, bad));
  EXPECT_EQ(slurp(p), before) << "the good file was changed by a failed write";
  EXPECT_EQ(entries(), std::vector<std::string>{"good.h5"});
  // A table attribute that collides with a reserved one fails as well.
  TableFile clash = sample_file();
  clash.tables[1].attributes["quantity"] = "clash";
  EXPECT_ANY_THROW(write_table_file(p, clash));
  EXPECT_EQ(slurp(p), before);
  EXPECT_EQ(entries(), std::vector<std::string>{"good.h5"});
  EXPECT_NO_THROW(read_table_file(p));
}

// Renaming onto a directory fails after the temporary was written: the
// directory stays and the temporary is removed.
TEST_F(TableFileTest, WriteOntoADirectoryThrowsAndCleansUp) {
  const std::string p = path("out.h5");
  fs::create_directory(p);
  std::ofstream(path("out.h5/keep")) << "x";
  EXPECT_ANY_THROW(write_table_file(p, sample_file()));
  EXPECT_TRUE(fs::is_directory(p));
  EXPECT_TRUE(fs::exists(path("out.h5/keep")));
  EXPECT_EQ(entries(), std::vector<std::string>{"out.h5"});
}

// Merging shards: batch estimates that are multiples of 2^-10 below 2^10
// add exactly in any order, so the merged sums are bit-identical to one table
// with all batches; with arbitrary doubles they agree to rounding.
// Batch values (kept by mcref validate's tables) round-trip with their "batch"
// dimension scale; values that do not add up to the stored sums are refused
// as damaged, and a table without them reads as before.
TEST_F(TableFileTest, BatchValuesRoundTripAndAreCheckedAgainstTheSums) {
  Table t("kept", "test_quantity", {Axis::uniform_bins("theta", "rad", 0, 1, 3), Axis::points("channel", "1", {0, 1})});
  t.keep_batch_values = true;
  Rng rng(31);
  for (int b = 0; b < 4; ++b) {
    std::vector<double> est(t.cells());
    for (double& x : est) x = rng.uniform();
    t.add_batch(est);
  }
  ASSERT_TRUE(t.has_batch_values());
  TableFile f;
  f.tables = {t, random_table("plain", {Axis::points("x", "1", {1, 2})}, 3, 5)};
  write_table_file(path("b.h5"), f);
  const TableFile back = read_table_file(path("b.h5"));
  ASSERT_TRUE(back.find("kept")->has_batch_values());
  EXPECT_EQ(back.find("kept")->batch_values, t.batch_values);
  EXPECT_FALSE(back.find("plain")->has_batch_values());
  {
    h5::Handle file(H5Fopen(path("b.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    h5::Handle ds(H5Dopen2(file, "kept/batch_values", H5P_DEFAULT), H5Dclose);
    h5::Handle space(H5Dget_space(ds), H5Sclose);
    hsize_t dims[3];
    ASSERT_EQ(H5Sget_simple_extent_dims(space, dims, nullptr), 3);
    EXPECT_EQ(dims[0], 4u);
    EXPECT_EQ(dims[1], 3u);
    EXPECT_EQ(dims[2], 2u);
    EXPECT_EQ(read_doubles(static_cast<hid_t>(file), "kept/batch"), (std::vector<double>{0, 1, 2, 3}));
  }
  Table damaged = t;
  damaged.batch_values[5] += 1e-9;
  f.tables = {damaged};
  write_table_file(path("d.h5"), f);
  EXPECT_NE(expect_config_error([&] { read_table_file(path("d.h5")); }, path("d.h5")).find("do not add up"), std::string::npos);
}

TEST(TableMerge, MergedShardsEqualOneTableWithAllBatches) {
  const std::vector<Axis> axes{Axis::points("theta_i", "rad", {0, 1}), Axis::uniform_bins("r", "1", 0, 1, 4)};
  for (bool dyadic : {true, false}) {
    Table all("t", "q", axes), a("t", "q", axes), b("t", "q", axes), c("t", "q", axes);
    Rng rng(17);
    for (int batch = 0; batch < 11; ++batch) {
      std::vector<double> est(all.cells());
      for (double& x : est) x = dyadic ? std::floor(rng.uniform() * 1024 * 64) / 1024 : rng.uniform() * 5 - 1;
      all.add_batch(est);
      (batch < 3 ? a : (batch < 7 ? b : c)).add_batch(est);
    }
    Table merged = a;
    merged.merge(b);
    merged.merge(c);
    EXPECT_EQ(merged.batches, all.batches);
    for (std::size_t i = 0; i < all.cells(); ++i) {
      if (dyadic) {
        EXPECT_EQ(merged.sum[i], all.sum[i]) << i;
        EXPECT_EQ(merged.sum_sq[i], all.sum_sq[i]) << i;
        EXPECT_EQ(merged.value(i), all.value(i)) << i;
        EXPECT_EQ(merged.stderr_of(i), all.stderr_of(i)) << i;
      } else {
        EXPECT_NEAR(merged.sum[i], all.sum[i], 1e-14 * std::fabs(all.sum[i]) + 1e-14) << i;
        EXPECT_NEAR(merged.sum_sq[i], all.sum_sq[i], 1e-14 * all.sum_sq[i]) << i;
        EXPECT_NEAR(merged.stderr_of(i), all.stderr_of(i), 1e-10 * all.stderr_of(i)) << i;
      }
    }
  }
}

TEST(TableMerge, MismatchedTablesRefuseToMerge) {
  Table t("t", "q", {Axis::uniform_bins("r", "1", 0, 1, 4)});
  Table other_name("u", "q", {Axis::uniform_bins("r", "1", 0, 1, 4)});
  Table other_edges("t", "q", {Axis::uniform_bins("r", "1", 0, 2, 4)});
  Table other_kind("t", "q", {Axis::points("r", "1", {0, 1, 2, 3})});
  EXPECT_THROW(t.merge(other_name), std::invalid_argument);
  EXPECT_THROW(t.merge(other_edges), std::invalid_argument);
  EXPECT_THROW(t.merge(other_kind), std::invalid_argument);
}

// value = mean of the batch estimates; stderr = sample sd / sqrt(batches).
TEST(TableStderr, FormulaMatchesSampleStandardDeviationOverRootN) {
  Table t("t", "q", {Axis::points("x", "1", {0, 1, 2})});
  const std::vector<std::vector<double>> batches{{1, 5, -2}, {2, 5, 0}, {3, 5, 2}, {4, 5, 4}};
  for (const auto& b : batches) t.add_batch(b);
  EXPECT_DOUBLE_EQ(t.value(0), 2.5);
  EXPECT_DOUBLE_EQ(t.stderr_of(0), std::sqrt((1.5 * 1.5 * 2 + 0.5 * 0.5 * 2) / 3 / 4));
  EXPECT_DOUBLE_EQ(t.value(1), 5);
  EXPECT_EQ(t.stderr_of(1), 0.0);  // constant: zero, not NaN
  EXPECT_DOUBLE_EQ(t.value(2), 1);
  EXPECT_DOUBLE_EQ(t.stderr_of(2), std::sqrt(20.0 / 3 / 4));
  EXPECT_EQ(t.values(), (std::vector<double>{t.value(0), t.value(1), t.value(2)}));
  // A two-pass reference on random batches.
  Table r("r", "q", {Axis::points("x", "1", {0})});
  Rng rng(23);
  std::vector<double> xs;
  for (int b = 0; b < 37; ++b) {
    xs.push_back(0.3 + rng.uniform());
    r.add_batch({xs.back()});
  }
  double mean = 0, ss = 0;
  for (double x : xs) mean += x / xs.size();
  for (double x : xs) ss += (x - mean) * (x - mean);
  EXPECT_NEAR(r.value(0), mean, 1e-14);
  EXPECT_NEAR(r.stderr_of(0), std::sqrt(ss / (xs.size() - 1) / xs.size()), 1e-12);
}

TEST(TableStderr, FewBatchesGiveNaN) {
  Table t("t", "q", {Axis::points("x", "1", {0})});
  EXPECT_TRUE(std::isnan(t.value(0)));
  EXPECT_TRUE(std::isnan(t.stderr_of(0)));
  t.add_batch({1.0});
  EXPECT_EQ(t.value(0), 1.0);
  EXPECT_TRUE(std::isnan(t.stderr_of(0)));
  EXPECT_THROW(t.add_batch({1.0, 2.0}), std::logic_error);
}

TEST(TableAxis, FindBinAndRowMajorIndex) {
  const Axis a = Axis::uniform_bins("r", "1", 0, 3, 3);
  EXPECT_EQ(a.find_bin(-1e-12), -1);
  EXPECT_EQ(a.find_bin(0), 0);
  EXPECT_EQ(a.find_bin(0.9999999), 0);
  EXPECT_EQ(a.find_bin(1), 1);
  EXPECT_EQ(a.find_bin(2.999), 2);
  EXPECT_EQ(a.find_bin(3), -1);
  EXPECT_EQ(a.find_bin(NAN), -1);
  const Axis b = Axis::bins("x", "1", {0, 0.1, 0.5, 2});
  EXPECT_EQ(b.find_bin(0.05), 0);
  EXPECT_EQ(b.find_bin(0.3), 1);
  EXPECT_EQ(b.find_bin(1.9), 2);
  Table t("t", "q", {Axis::points("p", "1", {1, 2}), a, b});
  EXPECT_EQ(t.cells(), 18u);
  EXPECT_EQ(t.index({1, 2, 1}), 1u * 9 + 2 * 3 + 1);
}

TEST(AzimuthBins, SameBinAsAtan2) {
  Rng rng(5);
  for (const bool folded : {true, false})
    for (const int bins : {1, 2, 3, 18, 360, 1000})
      for (const double phi_i : {0.0, 0.7, 3.5, -2.0}) {
        const AzimuthBins az(bins, phi_i, folded);
        const double span = folded ? kPi : 2 * kPi;
        int edge_cases = 0;
        for (int k = 0; k < 20000; ++k) {
          const double a = 2 * kPi * rng.uniform(), r = rng.uniform();
          const Vec3 w{r * std::cos(a), r * std::sin(a), 0.3};
          const double x = relative_azimuth(spherical_phi(w), phi_i, folded) / span * bins;
          const int expected = std::min(bins - 1, static_cast<int>(x));
          const int got = az.bin(w);
          // Only a direction within rounding of an edge may land on the other side.
          const double from_edge = std::fabs(x - std::round(x)) * span / bins;
          if (got != expected && from_edge < 1e-12) ++edge_cases;
          else EXPECT_EQ(got, expected) << bins << " " << phi_i << " " << a;
        }
        EXPECT_LE(edge_cases, 2);
      }
  const AzimuthBins az(18, 0.0, true);
  EXPECT_EQ(az.bin({0, 0, 1}), 0);  // straight up: bin 0, as atan2(0, 0) = 0
  EXPECT_EQ(az.bin({-1, 0, 0}), 17);
  EXPECT_EQ(az.bin({1, 1e-300, 0}), 0);
  // Signed zeros count as positive, as atan2 does not for -0.
  for (const bool folded : {true, false}) {
    const AzimuthBins a(18, 0.0, folded);
    EXPECT_EQ(a.bin({-0.0, -0.0, -1}), 0);
    EXPECT_EQ(a.bin({1, -0.0, 0}), 0);
    EXPECT_EQ(a.bin({-0.0, 1, 0}), folded ? 9 : 4);
  }
}
