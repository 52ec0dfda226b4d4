#pragma once
// Evaluates the analytic micrograin models on the cells of a simulated
// table, as the simulation measures them: bin averages over binned axes
// (with the same weighting the estimator applies), point values on point axes.
#include <string>
#include <vector>

#include "sim/geometry/micrograin_field.h"
#include "sim/tally/table.h"

namespace mcref {

struct ModelInfo {
  std::string name;         // e.g. "tau_plus_eq22"
  std::string quantity;     // table quantity it predicts
  bool exact;               // exact for a Poisson grain field (disagreement = a bug)
  std::string description;  // what it is, with equation numbers
};

// All models known for a table quantity (empty if none).
std::vector<ModelInfo> models_for(const std::string& quantity);
const ModelInfo* find_model(const std::string& name);
// Model values on the cells of `table` (same layout as table.values()).
// Throws std::invalid_argument for a model that does not fit the table.
std::vector<double> evaluate_model(const std::string& model, const Table& table, const MicrograinGeometry& geometry);

}  // namespace mcref
