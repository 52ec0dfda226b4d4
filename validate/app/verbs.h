#pragma once
// The verbs of the mcref command. Each returns the process exit code and
// throws ConfigError for bad input (printed by main as one line).
#include <set>
#include <string>
#include <vector>

#include "sim/files/input_file.h"

namespace mcref::cli {

int simulate(const std::vector<std::string>& args, const std::string& command_line);
int validate(const std::vector<std::string>& args, const std::string& command_line);
int info(const std::vector<std::string>& args);
int export_vdb(const std::vector<std::string>& args);
int export_brdf(const std::vector<std::string>& args);
int dataset(const std::vector<std::string>& args, const std::string& command_line);
int merge(const std::vector<std::string>& args);

// Small argument parser shared by the verbs.
struct Args {
  std::vector<std::string> positional;
  std::string output;
  std::vector<std::string> sets;
  long long seed = -1;
  int threads = 0;
  bool quiet = false;
  bool help = false;
  bool force = false;
  std::vector<std::string> cases;  // validate --case PATTERN (shell wildcards), any of them
  std::vector<std::string> tables;  // simulate --table NAME: only these tables
  bool batch_values = false;        // simulate --batch-values: the tables keep each batch's estimates
};
// An integer command-line value in [lo, hi] (ConfigError naming the flag otherwise).
long long parse_integer(const std::string& flag, const std::string& value, long long lo, long long hi);
// ConfigError if the single-valued option `name` was seen before (each
// parser keeps its `seen`): a second -o or --threads is refused, not taken.
void given_once(std::set<std::string>& seen, const std::string& name, const std::string& flag);
Args parse_args(const std::vector<std::string>& args, const std::string& verb, bool allow_set_and_seed);
// The files a run reads (`files`, then `more`: an experiment's own inputs), none of which an output may overwrite.
std::vector<std::string> with_inputs(std::vector<std::string> files, const std::vector<InputFile>& more);

}  // namespace mcref::cli
