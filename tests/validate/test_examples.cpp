// Every example shipped in validate/ parses and validates: experiments,
// suites (with their overrides) and datasets (first and last entry), and the
// quick experiment runs end to end. Keeps the examples from rotting.
#include <gtest/gtest.h>

#include <filesystem>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_entry.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "validate/suite.h"

namespace fs = std::filesystem;
using namespace mcref;

namespace {
std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(fs::path(MCREF_SOURCE_DIR) / dir))
    if (e.path().extension() == ".toml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

TEST(Examples, EveryExperimentParses) {
  const auto files = files_in("validate/experiments");
  ASSERT_GE(files.size(), 20u);
  for (const std::string& f : files) EXPECT_NO_THROW(load_experiment(f)) << f;
}

TEST(Examples, EverySuiteAndItsCasesParse) {
  const auto suites = files_in("validate/suites");
  ASSERT_GE(suites.size(), 4u);  // default, slab, micrograin_brdf, spheres
  for (const std::string& f : suites) {
    Suite s;
    ASSERT_NO_THROW(s = load_suite(f)) << f;
    EXPECT_FALSE(s.cases.empty()) << f;
    for (const Case& c : s.cases) EXPECT_NO_THROW(load_experiment(c.experiment_path, c.sets)) << f << ": " << c.name;
    EXPECT_NO_THROW(plan_suite(s, 2)) << f;  // every check names a table its case writes and a model of it
  }
}

TEST(Examples, EveryDatasetParsesAndItsEntriesValidate) {
  int datasets = 0;
  for (const std::string& f : files_in("validate/datasets")) {
    if (f.find("_base.toml") != std::string::npos) continue;  // a base experiment, not a dataset
    ++datasets;
    DatasetConfig d;
    ASSERT_NO_THROW(d = load_dataset(f)) << f;
    ASSERT_GT(d.entries(), 0) << f;
    for (std::int64_t i : {std::int64_t(0), d.entries() - 1})
      EXPECT_NO_THROW(entry_experiment(d, plan_entry(d, i))) << f << " entry " << i;
  }
  EXPECT_GE(datasets, 8);  // the eight shipped (validate/datasets)
}

// The quick experiment covers every micrograin quantity; 8 batches, < 2 s.
TEST(Examples, QuickExperimentRuns) {
  const Experiment ex = load_experiment((fs::path(MCREF_SOURCE_DIR) / "validate/experiments/quick.toml").string());
  SimulateOptions o;
  o.quiet = true;
  const std::vector<Table> tables = simulate(ex, o);
  EXPECT_EQ(tables.size(), 10u);
  for (const Table& t : tables) EXPECT_EQ(t.batches, ex.run.batches) << t.name;
}
