#pragma once
// The results of a validation run: OUTDIR/results.json (every check, its
// verdict and per-cell model values, the energy shares, error budgets and
// provenance of each case). scripts/plot_validation.py draws the plots from it
// and the tables, scripts/report.py renders report.html from it and the plots.
#include <string>
#include <vector>

#include "sim/hdf5/table_file.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"

namespace mcref {

struct Suite;
struct SuiteOptions;

struct CheckResult {
  std::string table, quantity, model, model_description;
  bool exact = false;
  double tolerance = 0;
  std::vector<double> model_values;
  ModelAccuracy accuracy;  // of an adaptive rule (integrals = 0: none reported)
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

// Writes OUTDIR/results.json and prints the failures, the counts (pass, FAIL,
// measured, n/a) and how to render the plots and the report.
void write_results(const Suite& suite, const std::vector<CaseResult>& results, const SuiteOptions& options);

}  // namespace mcref
