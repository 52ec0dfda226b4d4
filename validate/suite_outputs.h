#pragma once
// The files `mcref validate` writes, checked before any case is simulated by
// the rules of sim/files/output_path.h:
//   - OUTDIR/tables/ is a writable directory, or can be created;
//   - OUTDIR/results.json and OUTDIR/tables/<case>.h5 of every case run can be
//     replaced: not directories, FIFOs, devices or sockets, and their
//     temporary names within the file system's name limit;
//   - no input (the suite, the suites it includes, the cases' experiments and
//     their geometry.density_vdb files) is OUTDIR/results.json or lies in
//     OUTDIR/tables/.
// Violations are ConfigError naming the path.
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "validate/suite.h"

namespace mcref {

// `experiments` are the cases' (plan_suite), in the suite's order.
void check_suite_outputs(const Suite& suite, const std::vector<Experiment>& experiments, const std::string& out_dir);

}  // namespace mcref
