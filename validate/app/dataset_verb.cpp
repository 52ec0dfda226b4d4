// mcref dataset DATASET.toml -o DATA.h5 [--shard K/N] [--threads N] [--quiet]
#include <cstdio>
#include <cstdlib>

#include "sim/dataset/dataset_config.h"
#include "sim/dataset/dataset_run.h"
#include "sim/experiment/config_error.h"
#include "sim/files/output_path.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

namespace {

const char* kHelp =
    "usage: mcref dataset DATASET.toml -o DATA.h5 [--shard K/N] [--threads N] [--quiet]\n"
    "                     [--stop-after N] [--lean]\n"
    "\n"
    "Simulates every entry of a dataset (a base experiment and the [[parameter]]s\n"
    "that vary from entry to entry: grids of values, or values sampled from ranges)\n"
    "and writes their parameters and tables to one HDF5 file. Entries depend only on\n"
    "(dataset seed, entry index): the file is the same for any thread count or shard split.\n"
    "Finished entries are kept in DATA.h5.parts/ as they complete: rerun the same\n"
    "command after an interruption to resume; DATA.h5 is assembled atomically at the end.\n"
    "  --shard K/N      only entries with index % N == K (writes a shard file; combine\n"
    "                   the N shards with `mcref merge`)\n"
    "  --threads N      worker threads per entry\n"
    "  --stop-after N   compute at most N new entries, then stop (rerun to continue)\n"
    "  --lean           write DATA.h5 with value and stderr as float32 and no sums\n"
    "                   (about 4x smaller; it cannot be merged or resumed any more)\n"
    "  --quiet          no progress line\n"
    "Under mpirun -np N, the ranks share the entries dynamically (a rank that\n"
    "finishes one takes the next); each writes its parts, rank 0 assembles DATA.h5:\n"
    "the same bytes as one process. Resume works with any N.\n";

}  // namespace

int dataset(const std::vector<std::string>& raw, const std::string& command_line) {
  DatasetRunOptions opt;
  std::vector<std::string> rest;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] == "--lean") {
      opt.lean = true;
      continue;
    }
    if (raw[i] != "--shard" && raw[i] != "--stop-after") {
      rest.push_back(raw[i]);
      continue;
    }
    if (i + 1 >= raw.size()) throw ConfigError("command line", raw[i], "needs a value");
    const std::string flag = raw[i], v = raw[++i];
    given_once(seen, flag, flag);
    if (flag == "--stop-after") {
      opt.stop_after = parse_integer(flag, v, 0, 1LL << 40);
      continue;
    }
    // Errors quote the whole K/N as given (3/2, 1/2/3, 0/0).
    const auto slash = v.find('/');
    const auto bad = [&](const std::string& why) { return ConfigError("command line", flag, "= " + v + " " + why); };
    if (slash == std::string::npos || v.find('/', slash + 1) != std::string::npos) throw bad("must be K/N with 0 <= K < N");
    try {
      opt.shards = static_cast<int>(parse_integer(flag, v.substr(slash + 1), 1, 1000000));
      opt.shard = static_cast<int>(parse_integer(flag, v.substr(0, slash), 0, opt.shards - 1));
    } catch (const ConfigError&) {
      throw bad("must be K/N with whole numbers 0 <= K < N <= 1000000");
    }
  }
  Args a = parse_args(rest, "dataset", false);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref dataset needs exactly one DATASET.toml (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o DATA.h5)");
  opt.output = a.output;
  opt.threads = a.threads;
  opt.quiet = a.quiet;
  opt.ranks = &Communicator::world();  // under mpirun: the entries spread over the ranks
  const DatasetConfig config = load_dataset(a.positional[0]);
  check_on_root(*opt.ranks, [&] {
    const std::vector<std::string> inputs = with_inputs({a.positional[0], config.experiment_file}, config.inputs);
    check_output_file(a.output, inputs);
    // DATA.h5.parts/: its part files are replaced, and removed once assembled.
    check_output_directory(a.output + ".parts", inputs);
    check_inputs_outside(a.output + ".parts", inputs, "mcref dataset -o " + a.output);
  });
  const DatasetRunSummary s = run_dataset(config, opt);
  if (!opt.ranks->root()) return 0;  // rank 0 reports for the job
  if (s.up_to_date) {
    if (!a.quiet) std::fprintf(stderr, "mcref dataset: %s is up to date (%lld entries)\n", a.output.c_str(),
                               static_cast<long long>(s.entries));
    return 0;
  }
  if (!a.quiet || !s.complete)
    std::fprintf(stderr, "mcref dataset: %lld entries (%lld simulated, %lld resumed), %.3g rays in %.1f s%s%s\n",
                 static_cast<long long>(s.entries), static_cast<long long>(s.computed),
                 static_cast<long long>(s.reused), s.rays, s.seconds, s.complete ? " -> " : "",
                 s.complete ? a.output.c_str() : "");
  if (!s.complete)
    std::fprintf(stderr, "mcref dataset: stopped with at most %lld entries to go (kept in %s.parts/); rerun to continue\n",
                 static_cast<long long>(s.entries - s.computed - s.reused), a.output.c_str());
  (void)command_line;
  return 0;
}

}  // namespace mcref::cli
