#pragma once
// A validation suite (TOML): cases, each an experiment (+ overrides) and the
// model checks to run on its tables. `run_suite` simulates what is missing or
// stale (cached tables are reused when their stored config equals the
// case's effective config), evaluates the models, writes
//   OUTDIR/tables/<case>.h5   the simulated tables
//   OUTDIR/results.json       every check: metrics, verdicts, model values per cell
// and returns the number of failed checks. The plots (OUTDIR/plots/, by
// scripts/plot_validation.py) and OUTDIR/report.html (scripts/report.py) are
// rendered from these afterwards, without simulating.
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/parallel/communicator.h"

namespace mcref {

struct Check {
  std::string table;  // table name in the case's file
  std::string model;  // see models_for()
  double tolerance = 0;  // approximate models: max relative error allowed (0: measured only)
};

struct Case {
  std::string name, figure, description;
  std::string file, key;           // where it is defined (suite file, "case.<i>"), for messages
  std::string experiment_path;     // resolved against the suite file's directory
  std::vector<std::string> sets;   // --set style overrides
  std::vector<Check> checks;       // empty: every model of every table, measured
};

struct Suite {
  std::string file, name, title;
  std::vector<std::string> files;  // this suite's file and every suite it includes
  double significance = 1e-3;  // alpha for exact models
  bool significance_given = false;  // set in the file (an included suite must then agree)
  std::vector<Case> cases;
};

Suite load_suite(const std::string& path);

struct SuiteOptions {
  std::string out_dir;
  int threads = 0;
  bool quiet = false;
  bool force = false;  // re-simulate even when cached tables are current
  std::string command_line;
  std::string scripts_dir;  // where plot_validation.py and report.py live (named in the closing hint)
  // Ranks each case's batches are spread over (sim/parallel/batch_loop.h);
  // rank 0 alone checks the models and writes tables and results.
  const Communicator* ranks = &Communicator::self();
};

// Every case's experiment, validated with its checks before anything is
// simulated: a ConfigError (suite file, case, model, table) for a case whose
// tables would not fit in memory on `threads` threads (0: as simulate
// decides), a check of a table the experiment does not write, or of a model
// that does not predict that table.
std::vector<Experiment> plan_suite(const Suite& suite, int threads);

int run_suite(const Suite& suite, const SuiteOptions& options);

}  // namespace mcref
