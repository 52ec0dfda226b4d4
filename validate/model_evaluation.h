#pragma once
// Evaluates the analytic models on the cells of a simulated table, as the
// simulation measures them: bin averages over binned axes (with the same
// weighting the estimator applies), point values on point axes.
// Models come in families, one file each (validate/<family>_models.cpp).
#include <functional>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/tally/table.h"

namespace mcref {

struct ModelInfo {
  std::string name;         // e.g. "tau_plus_eq22"
  std::string quantity;     // table quantity it predicts
  bool exact;               // exact for the simulated geometry (disagreement = a bug)
  std::string description;  // what it is, with equation numbers
  std::string kind = "";    // geometry kind it applies to ("micrograin", "slab", "spheres")
  // Optional: which table component it predicts (e.g. "order1_grain"); empty = any.
  std::string component = "";
};

// Accuracy of the micrograin geometry statistics' bin averages (NDF, vNDF,
// conditional masking, g1_g_dist) and of the micrograin BRDF cell averages and
// albedo hemispheres (issue #15, part 4), as tested against references
// (tests/validate/micrograin/test_geometry_cell_average.cpp,
// test_brdf_cell_average.cpp). The slab and sphere families still use fixed
// per-cell rules (validate/slab, validate/spheres).
constexpr double kCellRelTolerance = 1e-6;

// Model values on the cells of `table` (same layout as table.values()).
using ModelEvaluator = std::function<std::vector<double>(const std::string& model, const Table&, const Experiment&)>;
using ModelStderrEvaluator = std::function<std::vector<double>(const std::string& model, const Table&, const Experiment&,
                                                               const std::vector<double>& values)>;
// Why a model does not apply to an experiment (an assumption of the model the
// experiment breaks, e.g. isotropic grains), or "" if it does.
using ModelAssumptions = std::function<std::string(const std::string& model, const Experiment&)>;

struct ModelFamily {
  std::vector<ModelInfo> models;
  ModelEvaluator evaluate;
  // Standard errors of models that are Monte Carlo estimates themselves,
  // given their values (empty result: the model has no noise of its own). Optional.
  ModelStderrEvaluator evaluate_stderr = nullptr;
  // Optional; checked before any evaluation (and before validate simulates).
  ModelAssumptions unsupported = nullptr;
};

// Progress inside one model evaluation. The caller sets a sink for its own
// thread (CellProgressScope); an evaluator that takes long reads it once at
// entry, before going parallel, and reports the table cells it finishes.
using CellsDone = std::function<void(std::size_t cells)>;
class CellProgressScope {
 public:
  explicit CellProgressScope(CellsDone sink);
  ~CellProgressScope();
  CellProgressScope(const CellProgressScope&) = delete;
  CellProgressScope& operator=(const CellProgressScope&) = delete;

 private:
  CellsDone previous_;
};
// The calling thread's sink (a no-op if none is set).
CellsDone cell_progress();

// Accuracy of a model evaluation by an adaptive rule that stops at a limit of
// refinements (the micrograin_brdf cell rule, validate/micrograin/brdf_cell_rule.h):
// over its integrals (a brdf cell, all channels; an albedo's hemisphere), how
// many stopped above the rule's relative target, and the largest relative error
// estimate reached. Order-independent, so it is the same for any thread count.
// Families with fixed rules report nothing (integrals = 0).
struct ModelAccuracy {
  double target = 0;            // the rule's relative error target
  std::size_t integrals = 0;    // integrals evaluated
  std::size_t unconverged = 0;  // of them, stopped at the limit above the target
  double worst_error = 0;       // largest relative error estimate reached
  std::size_t worst_cell = 0;   // flat index of the first table cell of that integral
  void add(std::size_t cell, double rel_error, bool converged, double rule_target);
  void merge(const ModelAccuracy& other);
};
// Where evaluations on the calling thread report their accuracy: set by the
// caller (like CellProgressScope); an evaluator reports once, on the calling
// thread, after its parallel loops (report_model_accuracy: merged into the
// scope's ModelAccuracy; a no-op if none is set).
class ModelAccuracyScope {
 public:
  explicit ModelAccuracyScope(ModelAccuracy* sink);
  ~ModelAccuracyScope();
  ModelAccuracyScope(const ModelAccuracyScope&) = delete;
  ModelAccuracyScope& operator=(const ModelAccuracyScope&) = delete;

 private:
  ModelAccuracy* previous_;
};
void report_model_accuracy(const ModelAccuracy& a);

// Calls fn(flat index, multi-index) for every cell of a table, row-major.
void for_each_cell(const Table& t, const std::function<void(std::size_t, const std::vector<std::size_t>&)>& fn);
// Index of the axis called `name` (std::invalid_argument if none).
std::size_t axis_index(const Table& t, const std::string& name);

// The families (each defined in its own file).
const ModelFamily& micrograin_geometry_models();
const ModelFamily& micrograin_brdf_models();
const ModelFamily& micrograin_phi_conditional_models();
const ModelFamily& slab_models();
const ModelFamily& sphere_models();

// All models of a table quantity for a geometry kind (empty if none).
std::vector<ModelInfo> models_for(const std::string& quantity, const std::string& kind = "micrograin");
const ModelInfo* find_model(const std::string& name);
// Why `model` cannot be evaluated on `table` of `ex` (another quantity or
// geometry kind, or an assumption of the model the experiment breaks), or ""
// if it can. Needs only the table's name, quantity and attributes, so it
// runs on empty tables before anything is simulated.
std::string model_mismatch(const std::string& model, const Table& table, const Experiment& ex);
// Throws std::invalid_argument for a model that does not fit the table (model_mismatch).
std::vector<double> evaluate_model(const std::string& model, const Table& table, const Experiment& experiment);
// Per-cell standard errors of a model's own Monte Carlo noise, given its
// values from evaluate_model; empty if it has none.
std::vector<double> evaluate_model_stderr(const std::string& model, const Table& table, const Experiment& experiment,
                                          const std::vector<double>& values);
// Micrograin geometry statistics only (kept for tests that build a geometry directly).
std::vector<double> evaluate_model(const std::string& model, const Table& table, const MicrograinGeometry& geometry);

}  // namespace mcref
