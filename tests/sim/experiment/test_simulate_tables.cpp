// SimulateOptions::tables: a simulation that returns only the tables named.
// The slab's BRDF tables not named are made without cells and never filled
// (slab_tables, make_brdf_tables' keep, BrdfBatch); every other kind computes all its
// tables and returns the named ones. Either way the returned tables are the
// bits of the full run (sum, sum_sq, batches, attributes), in the
// experiment's order, for both slab walks and on 1 and 2 threads. A name the
// experiment does not write is refused (ConfigError) before any path, naming
// it and the tables there are.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/experiment/simulate_kinds.h"
#include "sim/tally/table.h"

using namespace mcref;

namespace {

std::string source(const std::string& name) { return std::string(MCREF_SOURCE_DIR) + "/validate/experiments/" + name; }

std::vector<Table> run(const Experiment& ex, int threads, const std::vector<std::string>& tables) {
  SimulateOptions o;
  o.threads = threads;
  o.quiet = true;
  o.tables = tables;
  return simulate(ex, o);
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// `part` is `full` restricted to `names`, in full's order, table for table the same bits.
void expect_restriction(const std::vector<Table>& full, const std::vector<Table>& part, const std::vector<std::string>& names) {
  std::vector<const Table*> expected;
  for (const Table& t : full)
    for (const std::string& n : names)
      if (t.name == n) expected.push_back(&t);
  ASSERT_EQ(expected.size(), names.size()) << "a name of the test is not a table of the experiment";
  ASSERT_EQ(part.size(), expected.size());
  for (std::size_t i = 0; i < part.size(); ++i) {
    const Table& a = *expected[i];
    const Table& b = part[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_GT(b.cells(), 0u) << b.name;
    EXPECT_EQ(a.batches, b.batches) << b.name;
    EXPECT_TRUE(same_bits(a.sum, b.sum)) << b.name;
    EXPECT_TRUE(same_bits(a.sum_sq, b.sum_sq)) << b.name;
    EXPECT_EQ(a.attributes, b.attributes) << b.name;
    EXPECT_EQ(a.shape(), b.shape()) << b.name;
  }
}

}  // namespace

TEST(SimulateTables, SlabTablesLeftOutDoNotChangeTheOthers) {
  // Two layers without a substrate: reflection and transmission, every order.
  // The names are not in the experiment's order, and one is an albedo table.
  const std::vector<std::string> names{"brdf_btdf_order2", "brdf", "brdf_albedo", "brdf_btdf_order1_volume"};
  for (const char* walk : {"scalar", "wave"}) {
    const Experiment ex = load_experiment(source("slab_two_layers.toml"),
                                          {"run.batches=3", "measure.0.samples=3000", std::string("geometry.walk=\"") + walk + "\""});
    const std::vector<Table> full = run(ex, 2, {});
    for (int threads : {1, 2}) {
      SCOPED_TRACE(std::string(walk) + " walk, " + std::to_string(threads) + " threads");
      expect_restriction(full, run(ex, threads, names), names);
    }
  }
}

// What simulate_slab fills: the tables named with their cells, the others without.
TEST(SimulateTables, SlabTablesNotNamedAreMadeWithoutCells) {
  const Experiment ex = load_experiment(source("slab_two_layers.toml"));
  const std::vector<std::string> names{"brdf", "brdf_btdf_albedo"};
  int with_cells = 0, without = 0;
  for (const std::vector<Table>& measure : slab_tables(ex, names))
    for (const Table& t : measure) {
      const bool named = t.name == names[0] || t.name == names[1];
      EXPECT_EQ(t.cells() > 0, named) << t.name;
      (named ? with_cells : without) += 1;
    }
  EXPECT_EQ(with_cells, 2);
  EXPECT_GE(without, 14);  // the other BRDF and BTDF tables
}

TEST(SimulateTables, OtherKindsReturnTheNamedTables) {
  const Experiment ex = load_experiment(source("micrograin_brdf_diffuse.toml"), {"run.batches=2", "measure.0.samples=400"});
  const std::vector<Table> full = run(ex, 2, {});
  const std::vector<std::string> names{"brdf_albedo", "brdf"};
  expect_restriction(full, run(ex, 2, names), names);
}

TEST(SimulateTables, RefusesATableTheExperimentDoesNotWrite) {
  const Experiment ex = load_experiment(source("slab_two_layers.toml"), {"run.batches=2", "measure.0.samples=10"});
  try {
    run(ex, 1, {"brdf", "brdf_order5"});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("\"brdf_order5\" is not a table"), std::string::npos) << what;
    EXPECT_NE(what.find("brdf_btdf_order4plus"), std::string::npos) << what;  // the tables there are
  }
}
