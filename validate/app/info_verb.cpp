#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "sim/experiment/config_error.h"
#include "sim/hdf5/table_file.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

int info(const std::vector<std::string>& raw) {
  Args a = parse_args(raw, "info", false);
  if (a.help) {
    std::fputs("usage: mcref info TABLES.h5\n\nPrints the tables of an mcref file: quantity, axes, batch count,\n"
               "the largest relative standard error, and the provenance.\n", stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw ConfigError("command line", "", "mcref info needs exactly one TABLES.h5");
  const TableFile f = read_table_file(a.positional[0]);
  const Provenance& p = f.provenance;
  std::printf("%s\n  mcref %s (commit %s), created %s, seed %llu\n  simulation fingerprint: %s\n  command: %s\n  source: %s\n",
              a.positional[0].c_str(), p.mcref_version.c_str(), p.git_commit.c_str(), p.created.c_str(),
              static_cast<unsigned long long>(p.seed), p.sim_fingerprint.empty() ? "none (an older mcref)" : p.sim_fingerprint.c_str(),
              p.command_line.c_str(), p.source_file.c_str());
  for (const Table& t : f.tables) {
    std::ostringstream axes;
    for (const Axis& ax : t.axes) {
      axes << (axes.tellp() > 0 ? " x " : "") << ax.name << "[" << ax.size() << (ax.kind == Axis::Kind::Bins ? " bins" : "") << "]";
    }
    double worst = 0;
    std::size_t empty = 0, judged = 0;
    for (std::size_t i = 0; i < t.cells(); ++i) {
      const double v = t.value(i), e = t.stderr_of(i);
      if (std::isnan(v)) ++empty;
      if (std::isfinite(v) && std::isfinite(e) && std::fabs(v) > 0) worst = std::fmax(worst, e / std::fabs(v)), ++judged;
    }
    // One batch gives no standard error (NaN): "0" would read as exact.
    char rel[48];
    if (t.batches < 2) std::snprintf(rel, sizeof rel, "n/a (one batch)");
    else if (judged == 0) std::snprintf(rel, sizeof rel, "n/a (no non-zero value)");
    else std::snprintf(rel, sizeof rel, "%.3g", worst);
    const std::string empties = empty ? "  empty cells=" + std::to_string(empty) : "";
    std::printf("  %-28s %-18s %s  batches=%lld%s  max rel. stderr=%s%s  [%s]\n", t.name.c_str(), t.quantity.c_str(),
                axes.str().c_str(), static_cast<long long>(t.batches), t.has_batch_values() ? " (values kept)" : "", rel,
                empties.c_str(), t.units.c_str());
  }
  std::printf("config:\n%s\n", p.config.c_str());
  return 0;
}

}  // namespace mcref::cli
