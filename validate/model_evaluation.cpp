#include "validate/model_evaluation.h"

#include <stdexcept>

namespace mcref {

namespace {
const std::vector<const ModelFamily*>& families() {
  static const std::vector<const ModelFamily*> f{&micrograin_geometry_models(), &micrograin_brdf_models(),
                                                 &slab_models(), &sphere_models()};
  return f;
}
thread_local CellsDone current_sink;
}  // namespace

CellProgressScope::CellProgressScope(CellsDone sink) : previous_(std::move(current_sink)) {
  current_sink = std::move(sink);
}
CellProgressScope::~CellProgressScope() { current_sink = std::move(previous_); }

CellsDone cell_progress() {
  if (current_sink) return current_sink;
  return [](std::size_t) {};
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
  for (const ModelFamily* f : families())
    for (const ModelInfo& m : f->models)
      if (m.name == name) return &m;
  return nullptr;
}

std::vector<double> evaluate_model(const std::string& model, const Table& table, const Experiment& ex) {
  for (const ModelFamily* f : families())
    for (const ModelInfo& m : f->models)
      if (m.name == model) {
        if (m.quantity != table.quantity)
          throw std::invalid_argument("model " + model + " predicts " + m.quantity + ", not " + table.quantity);
        if (m.kind != ex.kind) throw std::invalid_argument("model " + model + " applies to " + m.kind + " geometry");
        return f->evaluate(model, table, ex);
      }
  throw std::invalid_argument("unknown model " + model);
}

std::vector<double> evaluate_model_stderr(const std::string& model, const Table& table, const Experiment& ex,
                                          const std::vector<double>& values) {
  for (const ModelFamily* f : families())
    for (const ModelInfo& m : f->models)
      if (m.name == model) return f->evaluate_stderr ? f->evaluate_stderr(model, table, ex, values) : std::vector<double>{};
  throw std::invalid_argument("unknown model " + model);
}

std::vector<double> evaluate_model(const std::string& model, const Table& table, const MicrograinGeometry& geometry) {
  Experiment ex;
  ex.kind = "micrograin";
  ex.micrograin = geometry;
  ex.isotropic = !geometry.anisotropic();
  return evaluate_model(model, table, ex);
}

}  // namespace mcref
