#include <cstdio>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/experiment/table_plan.h"
#include "sim/files/output_path.h"
#include "sim/hdf5/table_file.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref simulate EXPERIMENT.toml -o TABLES.h5 [--seed N] [--threads N]\n"
    "                      [--set key=value]... [--table NAME]... [--batch-values] [--quiet]\n"
    "\n"
    "Simulates every [[measure]] of the experiment on run.batches independent\n"
    "realizations of the geometry and writes one table per measure to TABLES.h5\n"
    "(written to a temporary file and renamed: never half-written).\n"
    "  --seed N         overrides run.seed\n"
    "  --threads N      worker threads (tables are identical for any N)\n"
    "  --set key=value  overrides a key, e.g. --set geometry.tau0=0.3 --set measure.0.samples=1e5\n"
    "  --table NAME     writes only this table (repeatable; default: every table); the\n"
    "                   slab's brdf tables not named are not computed, the others are the same\n"
    "  --batch-values   also writes each batch's estimates (batch_values: 8 bytes per cell\n"
    "                   and batch), from which verdicts estimate the cells' correlation\n"
    "  --quiet          no progress line\n"
    "Under mpirun -np N, the batches are spread over the N ranks and rank 0 writes\n"
    "TABLES.h5: the same tables as one process.\n";
}  // namespace

int simulate(const std::vector<std::string>& raw, const std::string& command_line) {
  Args a = parse_args(raw, "simulate", true);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref simulate needs exactly one EXPERIMENT.toml (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o TABLES.h5)");
  std::vector<std::string> sets = a.sets;
  if (a.seed >= 0) sets.push_back("run.seed=" + std::to_string(a.seed));
  const Experiment ex = load_experiment(a.positional[0], sets);
  check_table_names(ex, a.tables, "command line", "--table");
  // Fail before simulating if the output cannot be written.
  SimulateOptions opt;
  opt.ranks = &Communicator::world();  // under mpirun: the batches spread over the ranks
  check_on_root(*opt.ranks, [&] { check_output_file(a.output, with_inputs({a.positional[0]}, ex.inputs)); });
  opt.threads = a.threads;
  opt.quiet = a.quiet;
  opt.tables = a.tables;
  opt.keep_batch_values = a.batch_values;
  SimulateSummary summary;
  TableFile out;
  out.tables = mcref::simulate(ex, opt, &summary);
  if (!opt.ranks->root()) return 0;  // rank 0 holds the tables and writes them
  out.provenance = make_provenance(ex.text, ex.file, ex.run.seed, command_line);
  write_table_file(a.output, out);
  if (!a.quiet)
    std::fprintf(stderr, "mcref simulate: %zu tables, %d batches, %.3g rays in %.1f s (%.3g rays/s) -> %s\n",
                 out.tables.size(), ex.run.batches, summary.rays, summary.seconds,
                 summary.rays / std::max(summary.seconds, 1e-9), a.output.c_str());
  return 0;
}

}  // namespace mcref::cli
