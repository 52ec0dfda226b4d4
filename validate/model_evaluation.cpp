#include "validate/model_evaluation.h"

#include <cmath>
#include <stdexcept>

namespace mcref {

namespace {

const std::vector<const ModelFamily*>& families() {
  static const std::vector<const ModelFamily*> f{&micrograin_geometry_models(), &micrograin_brdf_models(), &micrograin_phi_conditional_models(),
                                                 &slab_models(), &sphere_models()};
  return f;
}
thread_local CellsDone current_sink;
thread_local ModelAccuracy* current_accuracy = nullptr;

// The family of a model, and its info (nullptr if unknown).
const ModelFamily* family_of(const std::string& model, const ModelInfo** info) {
  for (const ModelFamily* f : families())
    for (const ModelInfo& m : f->models)
      if (m.name == model) {
        *info = &m;
        return f;
      }
  return nullptr;
}

}  // namespace

CellProgressScope::CellProgressScope(CellsDone sink) : previous_(std::move(current_sink)) {
  current_sink = std::move(sink);
}
CellProgressScope::~CellProgressScope() { current_sink = std::move(previous_); }

CellsDone cell_progress() {
  if (current_sink) return current_sink;
  return [](std::size_t) {};
}

void ModelAccuracy::add(std::size_t cell, double rel_error, bool converged, double rule_target) {
  ModelAccuracy one;
  one.target = rule_target;
  one.integrals = 1;
  one.unconverged = converged ? 0 : 1;
  one.worst_error = rel_error;
  one.worst_cell = cell;
  merge(one);
}

void ModelAccuracy::merge(const ModelAccuracy& o) {
  if (o.integrals == 0) return;
  // The worst integral, the lowest cell among equals: the same in any order.
  if (integrals == 0 || o.worst_error > worst_error || (o.worst_error == worst_error && o.worst_cell < worst_cell)) {
    worst_error = o.worst_error;
    worst_cell = o.worst_cell;
  }
  target = std::fmax(target, o.target);
  integrals += o.integrals;
  unconverged += o.unconverged;
}

ModelAccuracyScope::ModelAccuracyScope(ModelAccuracy* sink) : previous_(current_accuracy) { current_accuracy = sink; }
ModelAccuracyScope::~ModelAccuracyScope() { current_accuracy = previous_; }

void report_model_accuracy(const ModelAccuracy& a) {
  if (current_accuracy) current_accuracy->merge(a);
}

void for_each_cell(const Table& t, const std::function<void(std::size_t, const std::vector<std::size_t>&)>& fn) {
  std::vector<std::size_t> idx(t.axes.size(), 0);
  for (std::size_t flat = 0; flat < t.cells(); ++flat) {
    fn(flat, idx);
    for (std::size_t d = t.axes.size(); d-- > 0;) {
      if (++idx[d] < t.axes[d].size()) break;
      idx[d] = 0;
    }
  }
}

std::size_t axis_index(const Table& t, const std::string& name) {
  for (std::size_t d = 0; d < t.axes.size(); ++d)
    if (t.axes[d].name == name) return d;
  throw std::invalid_argument("table " + t.name + " has no axis " + name);
}

std::vector<ModelInfo> models_for(const std::string& quantity, const std::string& kind) {
  std::vector<ModelInfo> out;
  for (const ModelFamily* f : families())
    for (const ModelInfo& m : f->models)
      if (m.quantity == quantity && m.kind == kind) out.push_back(m);
  return out;
}

const ModelInfo* find_model(const std::string& name) {
  const ModelInfo* m = nullptr;
  family_of(name, &m);
  return m;
}

std::string model_mismatch(const std::string& model, const Table& table, const Experiment& ex) {
  const ModelInfo* m = nullptr;
  const ModelFamily* f = family_of(model, &m);
  if (!f) return "unknown model " + model;
  if (m->quantity != table.quantity || m->kind != ex.kind)
    return "model " + model + " predicts " + m->quantity + " tables of " + m->kind + " geometry, and table " + table.name +
           " is " + table.quantity + " of " + ex.kind + " geometry";
  return f->unsupported ? f->unsupported(model, ex) : "";
}

std::vector<double> evaluate_model(const std::string& model, const Table& table, const Experiment& ex) {
  const std::string why = model_mismatch(model, table, ex);
  if (!why.empty()) throw std::invalid_argument(why);
  const ModelInfo* m = nullptr;
  return family_of(model, &m)->evaluate(model, table, ex);
}

std::vector<double> evaluate_model_stderr(const std::string& model, const Table& table, const Experiment& ex,
                                          const std::vector<double>& values) {
  const ModelInfo* m = nullptr;
  const ModelFamily* f = family_of(model, &m);
  if (!f) throw std::invalid_argument("unknown model " + model);
  return f->evaluate_stderr ? f->evaluate_stderr(model, table, ex, values) : std::vector<double>{};
}

std::vector<double> evaluate_model(const std::string& model, const Table& table, const MicrograinGeometry& geometry) {
  Experiment ex;
  ex.kind = "micrograin";
  ex.micrograin = geometry;
  ex.isotropic = !geometry.anisotropic();
  return evaluate_model(model, table, ex);
}

}  // namespace mcref
