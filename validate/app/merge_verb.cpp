// mcref merge A.h5 B.h5 ... -o DATA.h5
#include <cstdio>

#include "sim/dataset/dataset_run.h"
#include "sim/experiment/config_error.h"
#include "sim/files/output_path.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

namespace {
const char* kHelp =
    "usage: mcref merge SHARD.h5... -o DATA.h5 [--lean] [--quiet]\n"
    "\n"
    "Combines the shard files written by `mcref dataset --shard K/N` (same dataset\n"
    "config, seed and simulation fingerprint; no entry twice; every entry present)\n"
    "into one dataset file, byte for byte the file a single-process run of this\n"
    "build would have written.\n"
    "  --lean   write value and stderr as float32 without the sums (about 4x smaller;\n"
    "           the result cannot be merged again; the shards must be full)\n";
}  // namespace

int merge(const std::vector<std::string>& raw) {
  std::vector<std::string> rest;
  bool lean = false;
  for (const std::string& r : raw) {
    if (r == "--lean") lean = true;
    else rest.push_back(r);
  }
  Args a = parse_args(rest, "merge", false);
  if (a.help) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.empty()) throw ConfigError("command line", "", "mcref merge needs shard files (see --help)");
  if (a.output.empty()) throw ConfigError("command line", "-o", "an output file is required (-o DATA.h5)");
  check_output_file(a.output, a.positional);
  const std::int64_t n = merge_datasets(a.positional, a.output, a.quiet, lean);
  if (!a.quiet)
    std::fprintf(stderr, "mcref merge: %lld entries from %zu files -> %s\n", static_cast<long long>(n),
                 a.positional.size(), a.output.c_str());
  return 0;
}

}  // namespace mcref::cli
