#include <fnmatch.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/experiment/config_error.h"
#include "sim/files/output_path.h"
#include "validate/app/verbs.h"
#include "validate/suite.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref validate SUITE.toml -o OUTDIR [--case PATTERN]... [--threads N] [--force] [--quiet]\n"
    "\n"
    "Runs every case of a validation suite: simulates its experiment (reusing\n"
    "OUTDIR/tables/<case>.h5 when its stored config and simulation fingerprint\n"
    "match this build's and it holds every checked table), compares each\n"
    "table with the analytic models, and writes OUTDIR/results.json. Render the\n"
    "plots and OUTDIR/report.html from them (no simulation) with\n"
    "scripts/plot_validation.py OUTDIR and scripts/report.py OUTDIR; scripts/run.sh\n"
    "does all three.\n"
    "Exit status: 0 if no check fails (approximate models are measured, not judged),\n"
    "1 if any fails, 2 on bad input (nothing run), 3 on an error while running\n"
    "(e.g. a full disk; the finished cases' tables are kept for the next run).\n"
    "  --case PATTERN  run only the cases whose name matches PATTERN (shell wildcards\n"
    "                  * ? [..]; quote it); repeat to run several; results.json and\n"
    "                  the report then hold those cases only\n"
    "  --quiet    no progress lines, no per-case lines, no rendering hint\n"
    "  --force    simulate again even when cached tables are current\n"
    "Under mpirun -np N, each case's batches are spread over the N ranks (the same\n"
    "tables as one process); rank 0 checks the models and writes everything.\n";
// Keeps the cases whose name matches any pattern (fnmatch); a pattern that
// matches no case is an error (a mistyped one would silently drop its cases).
void select_cases(Suite& suite, const std::vector<std::string>& patterns) {
  std::vector<Case> kept;
  for (const Case& c : suite.cases)
    for (const std::string& p : patterns)
      if (fnmatch(p.c_str(), c.name.c_str(), 0) == 0) {
        kept.push_back(c);
        break;
      }
  for (const std::string& p : patterns) {
    const bool matched =
        std::any_of(suite.cases.begin(), suite.cases.end(), [&](const Case& c) { return fnmatch(p.c_str(), c.name.c_str(), 0) == 0; });
    if (matched) continue;
    std::string names;
    for (std::size_t k = 0; k < suite.cases.size() && k < 8; ++k) names += (k ? ", " : "") + suite.cases[k].name;
    if (suite.cases.size() > 8) names += ", ...";
    throw ConfigError("command line", "--case", "'" + p + "' matches no case of " + suite.file + " (its cases: " + names + ")");
  }
  suite.cases = std::move(kept);
}

}  // namespace

int validate(const std::vector<std::string>& raw, const std::string& command_line) {
  Args a = parse_args(raw, "validate", false);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref validate needs exactly one SUITE.toml (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output directory is required (-o OUTDIR)");
  Suite suite = load_suite(a.positional[0]);
  if (!a.cases.empty()) select_cases(suite, a.cases);
  SuiteOptions o;
  o.ranks = &Communicator::world();  // under mpirun: each case's batches spread over the ranks
  check_on_root(*o.ranks, [&] { check_output_directory(a.output, suite.files); });
  o.out_dir = a.output;
  o.threads = a.threads;
  o.quiet = a.quiet;
  o.force = a.force;
  o.command_line = command_line;
  o.scripts_dir = MCREF_SCRIPTS_DIR;
  return run_suite(suite, o) > 0 ? 1 : 0;
}

}  // namespace mcref::cli
