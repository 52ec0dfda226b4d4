// sim/dataset: dataset configs and entries. Entries are a deterministic
// function of (dataset seed, entry index); grids run in a stated order;
// counts drop array elements (and their parameters); bad input is a one-line
// ConfigError naming the file, the key and the allowed range.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_entry.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/slab_vdb.h"

namespace fs = std::filesystem;
using mcref::ConfigError;
using mcref::DatasetConfig;

namespace {

const char* kBase = R"(
[geometry]
kind = "slab"

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8

[[geometry.layer]]
phase = "isotropic"
thickness = 1.0
density = 1.0
albedo = 0.5

[run]
seed = 1
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [30]
theta_o_bins = 3
phi_bins = 2
samples = 100
)";

const char* kSampled = R"(
[dataset]
experiment = "base.toml"
entries = 5
seed = 11

[[parameter]]
key = "geometry.layer.count"
values = [1, 2]

[[parameter]]
key = "geometry.layer.0.alpha"
range = [0.05, 1.0]
distribution = "log_uniform"

[[parameter]]
key = "geometry.layer.0.phase"
choices = ["sggx_surface", "sggx_fiber"]

[[parameter]]
key = "geometry.layer.0.albedo"
range = [0.2, 1.0]
size = 3

[[parameter]]
key = "geometry.layer.0.orientation"
distribution = "direction"

[[parameter]]
key = "geometry.layer.1.albedo"
range = [0.0, 1.0]
)";

class DatasetConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mcref_test_dataset_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write("base.toml", kBase);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  DatasetConfig parse(const std::string& text) {
    write("ds.toml", text);
    return mcref::load_dataset((dir_ / "ds.toml").string());
  }
  // The ConfigError message of parsing and validating every entry ("" if none).
  std::string error_of(const std::string& text) {
    try {
      const DatasetConfig c = parse(text);
      for (std::int64_t i = 0; i < c.entries(); ++i) mcref::entry_experiment(c, mcref::plan_entry(c, i));
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

std::string dataset_with(const std::string& parameter, const std::string& entries = "entries = 2") {
  return "[dataset]\nexperiment = \"base.toml\"\n" + entries + "\n\n[[parameter]]\n" + parameter + "\n";
}

}  // namespace

TEST_F(DatasetConfigTest, EntriesAreAFunctionOfSeedAndIndex) {
  const DatasetConfig c = parse(kSampled);
  EXPECT_EQ(c.entries(), 10);  // 2 grid points x 5 sampled entries
  const std::vector<std::string> expected_columns{
      "geometry.layer.count",        "geometry.layer.0.alpha",          "geometry.layer.0.phase",
      "geometry.layer.0.albedo[0]",  "geometry.layer.0.albedo[1]",      "geometry.layer.0.albedo[2]",
      "geometry.layer.0.orientation[0]", "geometry.layer.0.orientation[1]", "geometry.layer.0.orientation[2]",
      "geometry.layer.1.albedo"};
  EXPECT_EQ(c.column_names(), expected_columns);
  const DatasetConfig again = parse(kSampled);
  for (std::int64_t i = 0; i < c.entries(); ++i) {
    const mcref::EntryPlan a = mcref::plan_entry(c, i), b = mcref::plan_entry(again, i);
    ASSERT_EQ(a.columns.size(), expected_columns.size());
    for (std::size_t k = 0; k < a.columns.size(); ++k)
      EXPECT_TRUE(a.columns[k] == b.columns[k] || (std::isnan(a.columns[k]) && std::isnan(b.columns[k])));
    EXPECT_EQ(a.assignments, b.assignments);
    EXPECT_EQ(a.seed, b.seed);
    // Grid: entries 0..4 have one layer, 5..9 two; layer 1 applies to the latter only.
    EXPECT_EQ(a.columns[0], i < 5 ? 1.0 : 2.0);
    EXPECT_EQ(std::isnan(a.columns[9]), i < 5);
    EXPECT_GE(a.columns[1], 0.05);
    EXPECT_LE(a.columns[1], 1.0);
    EXPECT_TRUE(a.columns[2] == 0 || a.columns[2] == 1);
    for (int k = 3; k < 6; ++k) EXPECT_TRUE(a.columns[k] >= 0.2 && a.columns[k] <= 1.0);
    const double norm = std::hypot(a.columns[6], a.columns[7], a.columns[8]);
    EXPECT_NEAR(norm, 1.0, 1e-12);
    EXPECT_GE(a.columns[8], 0.0);
    const mcref::Experiment ex = mcref::entry_experiment(c, a);
    EXPECT_EQ(ex.slab.layers.size(), i < 5 ? 1u : 2u);
    EXPECT_EQ(ex.run.seed, a.seed);
    EXPECT_DOUBLE_EQ(ex.slab.layers[0].alpha, a.columns[1]);  // exact: the value is set, not printed
    EXPECT_EQ(ex.slab.layers[0].alpha, a.columns[1]);
  }
  // Entries differ from each other and with the seed.
  EXPECT_NE(mcref::plan_entry(c, 0).columns[1], mcref::plan_entry(c, 1).columns[1]);
  EXPECT_NE(mcref::plan_entry(c, 0).seed, mcref::plan_entry(c, 1).seed);
  std::string reseeded = kSampled;
  reseeded.replace(reseeded.find("seed = 11"), 9, "seed = 12");
  EXPECT_NE(mcref::plan_entry(parse(reseeded), 0).columns[1], mcref::plan_entry(c, 0).columns[1]);
}

TEST_F(DatasetConfigTest, AddingAParameterLeavesTheOthersAlone) {
  const DatasetConfig c = parse(kSampled);
  const DatasetConfig more = parse(std::string(kSampled) + "\n[[parameter]]\nkey = \"geometry.layer.1.thickness\"\nrange = [0.5, 2]\n");
  for (std::int64_t i = 0; i < c.entries(); ++i)
    EXPECT_EQ(mcref::plan_entry(c, i).columns[1], mcref::plan_entry(more, i).columns[1]);
}

TEST_F(DatasetConfigTest, GridRunsLastParameterFastest) {
  write("grain.toml", R"(
[geometry]
kind = "micrograin"
tau0 = 0.5
beta = 0.8
tile = 40
[run]
batches = 2
[[measure]]
quantity = "tau_plus"
theta_i_deg = [0, 60]
samples = 100
)");
  const DatasetConfig c = parse(R"(
[dataset]
experiment = "grain.toml"
[[parameter]]
key = "geometry.tau0"
values = [0.2, 0.4, 0.6]
[[parameter]]
key = "geometry.beta"
values = [0.5, 1.5]
)");
  ASSERT_EQ(c.entries(), 6);
  const double tau0[] = {0.2, 0.2, 0.4, 0.4, 0.6, 0.6}, beta[] = {0.5, 1.5, 0.5, 1.5, 0.5, 1.5};
  for (int i = 0; i < 6; ++i) {
    const mcref::EntryPlan p = mcref::plan_entry(c, i);
    EXPECT_EQ(p.columns, (std::vector<double>{tau0[i], beta[i]}));
    const mcref::Experiment ex = mcref::entry_experiment(c, p);
    EXPECT_EQ(ex.micrograin.tau0, tau0[i]);
    EXPECT_EQ(p.assignments[0], "geometry.tau0=" + std::string(i < 2 ? "0.2" : i < 4 ? "0.4" : "0.6"));
  }
}

TEST_F(DatasetConfigTest, CategoricalValuesAndWholeTables) {
  const DatasetConfig c = parse(R"(
[dataset]
experiment = "base.toml"
[[parameter]]
key = "geometry.layer.1"
values = [{ phase = "isotropic", thickness = 2.0, density = 1.0 }, { phase = "hg", g = 0.5, thickness = 1.0, density = 3.0 }]
)");
  ASSERT_EQ(c.entries(), 2);
  EXPECT_TRUE(c.parameters[0].categorical());
  EXPECT_EQ(mcref::plan_entry(c, 1).columns, std::vector<double>{1.0});
  const mcref::Experiment ex = mcref::entry_experiment(c, mcref::plan_entry(c, 1));
  EXPECT_EQ(ex.slab.layers[1].g, 0.5);
  EXPECT_EQ(ex.slab.layers[1].density, 3.0);
}

TEST_F(DatasetConfigTest, BadInputNamesFileKeyAndRange) {
  auto expect = [&](const std::string& text, std::vector<std::string> parts) {
    const std::string e = error_of(text);
    ASSERT_FALSE(e.empty()) << text;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const std::string& p : parts) EXPECT_NE(e.find(p), std::string::npos) << "'" << p << "' not in: " << e;
  };
  expect(dataset_with("key = \"geometry.layer.0.alphaa\"\nvalues = [0.1]", ""),
         {"ds.toml", "entry 0", "geometry.layer.0.alphaa"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nrange = [1.0, 0.1]"), {"ds.toml", "parameter.0.range", "lo < hi"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nrange = [0, 1]\ndistribution = \"log_uniform\""),
         {"parameter.0.range", "0 < lo"});
  expect(dataset_with("key = \"geometry.layer.0.albedo\"\nrange = [0.5, 1.5]", "entries = 20"),
         {"ds.toml", "entry", "geometry.layer.0.albedo", "[0, 1]"});
  expect(dataset_with("key = \"geometry.layer.count\"\nvalues = [1, 3]", ""), {"parameter.0.values", "[1, 2]"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nrange = [0.1, 1]", ""), {"dataset.entries", "required"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nrange = [0.1, 1]\ndistribution = \"gauss\""),
         {"parameter.0.distribution", "log_uniform"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nvalue = [0.1]"), {"parameter.0.value", "allowed"});
  expect(dataset_with("key = \"geometry.layer.7.alpha\"\nvalues = [0.1]", ""), {"geometry.layer.7.alpha", "[0, 2)"});
  expect("[dataset]\nexperiment = \"missing.toml\"\n", {"ds.toml", "dataset.experiment", "missing.toml"});
  expect("[dataset]\nexperiment = \"base.toml\"\nsed = 3\n", {"dataset.sed"});
  expect("[dataset]\nexperiment = \"base.toml\"\ncompression = 12\n", {"dataset.compression", "9"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nvalues = [0.1]\n[[parameter]]\nkey = \"geometry.layer.0.alpha\"\nvalues = [0.2]", ""),
         {"parameter.1.key", "twice"});
  expect(dataset_with("key = \"geometry.layer.0.alpha\"\nvalues = [0.1]", "tables = [\"brdf\", \"brdf\"]"),
         {"ds.toml", "dataset.tables", "\"brdf\" twice"});  // was found after the first entry's simulation
  // 1024^7 = 2^70 grid points wrapped to 0: an empty dataset, exit 0.
  std::string wide = "[dataset]\nexperiment = \"base.toml\"\n", values = "[0";
  for (int v = 1; v < 1024; ++v) values += ", " + std::to_string(v);
  for (int k = 0; k < 7; ++k) wide += "\n[[parameter]]\nkey = \"geometry.layer.0.p" + std::to_string(k) + "\"\nvalues = " + values + "]\n";
  expect(wide, {"ds.toml", "parameter.4.values", "2^40"});
}

// A value out of range is blamed on its own parameter: layer 1's albedo drawn
// from [0.5, 1.5] beside a layer count in [1, 2] was reported as the count's
// fault ("2 (values) makes an invalid experiment") when entry 0 drew 1.5.
TEST_F(DatasetConfigTest, AnInvalidValueIsBlamedOnItsOwnParameter) {
  int drew_the_bad_one = 0;
  for (int seed = 1; seed <= 8; ++seed) {
    const DatasetConfig c = parse("[dataset]\nexperiment = \"base.toml\"\nentries = 1\nseed = " + std::to_string(seed) +
                                  "\n[[parameter]]\nkey = \"geometry.layer.count\"\nvalues = [1, 2]\n"
                                  "[[parameter]]\nkey = \"geometry.layer.1.albedo\"\nchoices = [0.5, 1.5]\n");
    std::string e;
    try {
      mcref::check_parameter_values(c);
    } catch (const ConfigError& x) {
      e = x.what();
    }
    ASSERT_NE(e.find("ds.toml: key 'geometry.layer.1.albedo': "), std::string::npos) << "seed " << seed << ": " << e;
    EXPECT_EQ(e.find("key 'geometry.layer.count'"), std::string::npos) << "seed " << seed << ": " << e;
    drew_the_bad_one += e.find("as drawn for entry 0") != std::string::npos;
  }
  EXPECT_GT(drew_the_bad_one, 0);  // the case that was misreported occurred
}

// A base experiment reading geometry.density_vdb: the file's content, with its
// path as the experiment gives it, is part of the dataset's identity (a changed
// file gives another identity; reaching the same files by another path does
// not); entries find the file beside the base experiment and refuse a file
// changed after the dataset was read; no parameter may vary the file.
TEST_F(DatasetConfigTest, DensityVdbContentIsPartOfTheIdentity) {
  const std::string slab = R"([geometry]
kind = "slab"
backend = "openvdb"
lateral_voxels = 2
depth_voxels = 2
)";
  const std::string layer = "[[geometry.layer]]\nphase = \"isotropic\"\nalbedo = 0.5\n";
  const std::string rest = "[run]\nbatches = 2\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";
  fs::create_directories(dir_ / "base");
  const auto export_density = [&](double rho) {
    const mcref::Experiment ex = mcref::parse_experiment(slab + layer + "density = " + std::to_string(rho) + "\n" + rest, "x.toml");
    mcref::volume::write_vdb((dir_ / "base" / "d.vdb").string(), mcref::volume::DensityGrids(ex.slab));
  };
  export_density(1.0);
  write("base/base.toml", slab + "density_vdb = \"d.vdb\"\n" + layer + rest);
  const std::string dataset = "[dataset]\nexperiment = \"base/base.toml\"\n\n[[parameter]]\n"
                              "key = \"geometry.layer.0.albedo\"\nvalues = [0.2, 0.4]\n";
  const DatasetConfig a = parse(dataset);
  EXPECT_NE(a.experiment_text.find("# geometry.density_vdb read from \"d.vdb\": bytes="), std::string::npos)
      << a.experiment_text;
  ASSERT_EQ(a.inputs.size(), 1u);
  EXPECT_EQ(a.inputs[0].path, (dir_ / "base" / "d.vdb").string());
  // The same files from another working directory (a relative path to the dataset file): the same identity.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  DatasetConfig same;
  try {
    same = mcref::load_dataset("ds.toml");
  } catch (...) {
    fs::current_path(cwd);
    throw;
  }
  fs::current_path(cwd);
  EXPECT_EQ(same.inputs[0].path, "base/d.vdb");
  EXPECT_EQ(same.experiment_text, a.experiment_text);
  const mcref::Experiment entry = mcref::entry_experiment(a, mcref::plan_entry(a, 1));
  EXPECT_DOUBLE_EQ(entry.slab.layers[0].density, 1.0);
  EXPECT_DOUBLE_EQ(entry.slab.layers[0].albedo.r, 0.4);
  // The file changed after the dataset was read: its entries refuse to run; read again, another identity.
  export_density(2.0);
  try {
    mcref::entry_experiment(a, mcref::plan_entry(a, 0));
    ADD_FAILURE() << "an entry ran on a changed density_vdb";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("d.vdb' changed after the dataset was read"), std::string::npos) << e.what();
  }
  const DatasetConfig b = parse(dataset);
  EXPECT_NE(a.experiment_text, b.experiment_text);
  EXPECT_DOUBLE_EQ(mcref::entry_experiment(b, mcref::plan_entry(b, 0)).slab.layers[0].density, 2.0);
  const std::string m = error_of(dataset_with("key = \"geometry.density_vdb\"\nchoices = [\"d.vdb\", \"e.vdb\"]", ""));
  EXPECT_NE(m.find("parameter.0.key': a dataset cannot vary geometry.density_vdb"), std::string::npos) << m;
}

// run.seed is the dataset's to set (from its seed and the entry index): a
// parameter on it would be recorded in the entries' assignments and then overridden.
TEST_F(DatasetConfigTest, RunSeedIsNotAParameter) {
  const std::string m = error_of(dataset_with("key = \"run.seed\"\nvalues = [1, 2]", ""));
  EXPECT_NE(m.find("parameter.0.key': a dataset sets every entry's run.seed itself"), std::string::npos) << m;
}
