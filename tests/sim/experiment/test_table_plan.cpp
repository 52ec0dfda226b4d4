// sim/experiment/table_plan.h: the cell count behind the memory estimate is
// an upper bound of the tables every measure really makes, within a few
// small derived tables, for every shipped experiment (each kind, each
// quantity, anisotropic, with and without substrate, volumetric spheres);
// the budget reads MCREF_MEMORY_LIMIT and refuses bad values.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/table_plan.h"

namespace fs = std::filesystem;
using namespace mcref;

TEST(TablePlan, CellCountBoundsTheTablesOfEveryShippedMeasure) {
  int measures = 0;
  for (const auto& e : fs::directory_iterator(fs::path(MCREF_SOURCE_DIR) / "validate/experiments")) {
    if (e.path().extension() != ".toml") continue;
    const Experiment ex = load_experiment(e.path().string());
    for (const Measure& m : ex.measures) {
      Experiment one = ex;
      one.measures = {m};
      double cells = 0;
      for (const Table& t : empty_tables(one)) {
        cells += static_cast<double>(t.cells());
        EXPECT_EQ(t.batches, 0);
      }
      const double dirs = static_cast<double>(std::max<std::size_t>(1, m.theta_i.size()) * std::max<std::size_t>(1, m.phi_i.size()));
      // Not written everywhere: slab _energy, spheres _modes and _kd (theta_i x theta_o x 3 modes x 3 channels + 3).
      const double slack = 3 * dirs + 9.0 * std::max<std::size_t>(1, m.theta_i.size()) * m.theta_o_bins + 3;
      EXPECT_GE(measure_cells(m, ex), cells) << e.path() << " measure " << m.name;
      EXPECT_LE(measure_cells(m, ex), cells + slack) << e.path() << " measure " << m.name;
      EXPECT_GE(memory_needed(one, 1), 48 * cells);
      ++measures;
    }
  }
  EXPECT_GE(measures, 30);
}

TEST(TablePlan, BudgetFollowsMcrefMemoryLimit) {
  ASSERT_EQ(setenv("MCREF_MEMORY_LIMIT", "3G", 1), 0);
  std::string why;
  EXPECT_EQ(memory_budget(&why), 3.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(why, "MCREF_MEMORY_LIMIT");
  const Experiment ex = load_experiment((fs::path(MCREF_SOURCE_DIR) / "validate/experiments/quick.toml").string());
  EXPECT_NO_THROW(check_memory(ex, 2));
  ASSERT_EQ(setenv("MCREF_MEMORY_LIMIT", "1K", 1), 0);
  try {
    check_memory(ex, 2);
    ADD_FAILURE() << "a 1 KB budget was enough";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("quick.toml: key 'measure."), std::string::npos) << what;
    EXPECT_NE(what.find("budget of 1 KB (MCREF_MEMORY_LIMIT)"), std::string::npos) << what;
  }
  for (const char* bad : {"lots", "-1G", "0", "5X", "1GB", "nan"}) {
    ASSERT_EQ(setenv("MCREF_MEMORY_LIMIT", bad, 1), 0);
    EXPECT_THROW(memory_budget(), ConfigError) << bad;
  }
  ASSERT_EQ(unsetenv("MCREF_MEMORY_LIMIT"), 0);
  EXPECT_GT(memory_budget(&why), 0);
  EXPECT_NE(why.find("half of the"), std::string::npos) << why;
}

TEST(TablePlan, BytesText) {
  EXPECT_EQ(bytes_text(512), "512 bytes");
  EXPECT_EQ(bytes_text(1536), "1.5 KB");
  EXPECT_EQ(bytes_text(3.0 * 1024 * 1024 * 1024), "3 GB");
}
