#pragma once
// The validation report: results.json (every check and its per-cell model
// values, read by scripts/plot_validation.py), plots, and report.html.
#include <string>
#include <vector>

#include "sim/hdf5/table_file.h"
#include "validate/metrics.h"

namespace mcref {

struct Suite;
struct SuiteOptions;

struct CheckResult {
  std::string table, quantity, model, model_description;
  bool exact = false;
  double tolerance = 0;
  std::vector<double> model_values;
  Comparison comparison;
  Verdict verdict;
};

// Share of the reflected (or transmitted) energy by scattering order, from an
// albedo table: one row per incident direction, channel 0.
struct EnergyShare {
  std::string table;
  double theta_i = 0, phi_i = 0, total = 0, single = 0, multiple = 0;
};

// Where an approximate single-scattering model's albedo error comes from
// (issue #3), for a model checked on an albedo table whose order-1
// components it predicts: with d = model - sim,
//   d(total) = sum over order-1 components of d  -  sim orders >= 2,
// the first term the error of the model's own single-scattering terms
// (masking, shadowing, pore visibility), the second the single-scattering
// assumption. Mean over the RGB channels the model is compared on; first
// azimuth of incidence.
struct ErrorBudget {
  std::string table, model;
  double theta_i = 0;
  double sim = 0, sim_stderr = 0, model_value = 0;
  double order1_error = 0;  // sum over order-1 components of (model - sim)
  double multiple = 0;      // sim energy in orders >= 2
};

struct CaseResult {
  std::string name, figure, description, table_file;
  bool reused = false;
  std::vector<EnergyShare> energy;
  std::vector<ErrorBudget> budget;
  Provenance provenance;
  std::vector<CheckResult> checks;
};

// Writes OUTDIR/results.json, runs the plot script, writes OUTDIR/report.html,
// and prints the summary and the report's path.
void write_report(const Suite& suite, const std::vector<CaseResult>& results, const SuiteOptions& options);

}  // namespace mcref
