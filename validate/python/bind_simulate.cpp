// mcref.simulate (experiment -> tables, as `mcref simulate`) and
// mcref.evaluate_model (a suite model on the cells of a table).
#include <toml++/toml.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <future>
#include <optional>
#include <sstream>
#include <thread>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/experiment/table_plan.h"
#include "sim/hdf5/table_file.h"
#include "validate/model_evaluation.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace {

const char* kDictFile = "<dict>";
const char* kTextFile = "<string>";

toml::table to_toml_table(const py::handle& dict, const std::string& key);
toml::array to_toml_array(const py::handle& list, const std::string& key);

// One Python value as a TOML node (bool before int: bool is an int in Python).
template <typename Insert>
void insert_value(const py::handle& v, const std::string& key, Insert insert) {
  if (py::isinstance<py::bool_>(v)) insert(toml::value<bool>(v.cast<bool>()));
  else if (py::isinstance<py::int_>(v)) {
    std::int64_t i = 0;
    try {
      i = v.cast<std::int64_t>();
    } catch (const py::cast_error&) {
      throw ConfigError(kDictFile, key, "= " + std::string(py::repr(v)) + " is out of range; allowed [-9223372036854775808, 9223372036854775807]");
    }
    insert(toml::value<std::int64_t>(i));
  }
  else if (py::isinstance<py::float_>(v)) insert(toml::value<double>(v.cast<double>()));
  else if (py::isinstance<py::str>(v)) insert(toml::value<std::string>(v.cast<std::string>()));
  else if (py::isinstance<py::dict>(v)) insert(to_toml_table(v, key));
  else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) insert(to_toml_array(v, key));
  else if (py::hasattr(v, "tolist")) insert_value(v.attr("tolist")(), key, insert);  // numpy arrays and scalars
  else throw ConfigError(kDictFile, key, "value of Python type " + std::string(py::str(v.get_type().attr("__name__"))) +
                                             " is not a TOML value (bool, int, float, str, list, dict)");
}

toml::table to_toml_table(const py::handle& dict, const std::string& key) {
  toml::table t;
  for (auto item : dict.cast<py::dict>()) {
    const std::string k = py::str(item.first);
    const std::string full = key.empty() ? k : key + "." + k;
    insert_value(item.second, full, [&](auto&& node) { t.insert_or_assign(k, std::move(node)); });
  }
  return t;
}

toml::array to_toml_array(const py::handle& list, const std::string& key) {
  toml::array a;
  std::size_t i = 0;
  for (auto item : list) insert_value(item, key + "." + std::to_string(i++), [&](auto&& node) { a.push_back(std::move(node)); });
  return a;
}

// A dict, TOML text, or a path to a TOML file -> (text, file name for messages).
std::pair<std::string, std::string> config_text(const py::object& config) {
  if (py::isinstance<py::dict>(config)) {
    const toml::table root = to_toml_table(config, "");
    std::ostringstream s;
    s << root;
    return {s.str(), kDictFile};
  }
  if (py::isinstance<py::str>(config)) {
    const std::string text = config.cast<std::string>();
    if (text.find('\n') == std::string::npos && text.find('=') == std::string::npos && text.size() > 5 &&
        text.compare(text.size() - 5, 5, ".toml") == 0)
      throw ConfigError("<python>", "config", "\"" + text + "\" looks like a file name; use mcref.simulate_file(path)");
    return {text, kTextFile};
  }
  throw ConfigError("<python>", "config", "must be a dict or TOML text (use open(path).read() or simulate_file(path))");
}

// simulate() on a thread of its own, the GIL released, while this thread runs
// Python's signal handlers every 0.1 s: on Ctrl-C (KeyboardInterrupt, or any
// exception a handler raises) the run is cancelled, and the exception is raised
// once it has stopped (within a measure of a batch).
std::vector<Table> simulate_interruptible(const Experiment& ex, SimulateOptions opt) {
  std::atomic<bool> cancel{false};
  opt.cancel = &cancel;
  std::vector<Table> tables;
  std::exception_ptr failure;
  std::optional<py::error_already_set> raised;
  {
    py::gil_scoped_release release;
    std::promise<void> finished;
    std::future<void> done = finished.get_future();
    std::thread worker([&] {
      try {
        tables = simulate(ex, opt);
      } catch (...) {
        failure = std::current_exception();
      }
      finished.set_value();
    });
    while (done.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
      if (raised) continue;
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        raised.emplace();  // takes the exception the handler raised
        cancel = true;
      }
    }
    worker.join();
  }
  if (raised) throw std::move(*raised);
  if (failure) std::rethrow_exception(failure);
  return tables;
}

TableFile run(const Experiment& ex, int threads, bool quiet, const std::vector<std::string>& tables, bool keep_batch_values,
              const std::string& call) {
  check_table_names(ex, tables, "<python>", "tables");
  SimulateOptions opt;
  opt.threads = threads;
  opt.quiet = quiet;
  opt.tables = tables;
  opt.keep_batch_values = keep_batch_values;
  TableFile out;
  out.tables = simulate_interruptible(ex, opt);
  out.provenance = make_provenance(ex.text, ex.file, ex.run.seed, call);
  return out;
}

std::vector<std::string> overrides(std::vector<std::string> sets, py::object seed) {
  if (!seed.is_none()) {
    sets.push_back("run.seed=" + std::to_string(integer_argument("seed", seed, INT64_MAX)));
  }
  return sets;
}

}  // namespace

void bind_simulate(py::module_& m) {
  m.def("simulate", [](py::object config, py::object seed, int threads, std::vector<std::string> sets, bool quiet,
                       std::vector<std::string> tables, bool keep_batch_values) {
    const auto [text, file] = config_text(config);
    const Experiment ex = parse_experiment(text, file, overrides(sets, seed));
    if (threads < 0 || threads > 1024) throw ConfigError("<python>", "threads", "= " + std::to_string(threads) + " must be an integer in [0, 1024]");
    return run(ex, threads, quiet, tables, keep_batch_values, "python: mcref.simulate");
  }, py::arg("config"), py::arg("seed") = py::none(), py::arg("threads") = 0,
        py::arg("sets") = std::vector<std::string>{}, py::arg("quiet") = true,
        py::arg("tables") = std::vector<std::string>{}, py::arg("keep_batch_values") = false,
        "Simulates an experiment given as a dict or as TOML text, with the keys of the\n"
        "experiment files (README: Experiment files). seed overrides run.seed (as --seed);\n"
        "threads: worker threads, 0 = run.threads (tables are identical for any count);\n"
        "sets: 'key=value' overrides (as --set); tables: only these tables, by name (as\n"
        "--table; default all); keep_batch_values: the tables keep each batch's estimates\n"
        "(Table.batch_values, 8 bytes per cell and batch), which judge() uses. Returns a TableFile whose tables are\n"
        "bit-identical to what `mcref simulate` writes for the same config and seed.\n"
        "Bad input raises mcref.ConfigError with the CLI's one-line message (the file is\n"
        "named '<dict>' or '<string>').");

  m.def("simulate_file", [](const std::filesystem::path& p, py::object seed, int threads, std::vector<std::string> sets,
                            bool quiet, std::vector<std::string> tables, bool keep_batch_values) {
    const std::string path = p.string();
    const Experiment ex = load_experiment(path, overrides(sets, seed));
    if (threads < 0 || threads > 1024) throw ConfigError("<python>", "threads", "= " + std::to_string(threads) + " must be an integer in [0, 1024]");
    return run(ex, threads, quiet, tables, keep_batch_values, "python: mcref.simulate_file " + path);
  }, py::arg("path"), py::arg("seed") = py::none(), py::arg("threads") = 0,
        py::arg("sets") = std::vector<std::string>{}, py::arg("quiet") = true,
        py::arg("tables") = std::vector<std::string>{}, py::arg("keep_batch_values") = false,
        "Same as simulate() for an experiment file: errors name the file exactly as `mcref simulate` does.");

  m.def("parse_config", [](py::object config) {
    const auto [text, file] = config_text(config);
    return parse_experiment(text, file).text;
  }, py::arg("config"), "Validates a config (dict or TOML text) and returns its canonical TOML text.");

  m.def("models", [](const std::string& quantity, const std::string& kind) {
    if (kind != "micrograin" && kind != "slab" && kind != "spheres")
      throw ConfigError("<python>", "kind", "\"" + kind + "\" must be one of micrograin, slab, spheres");
    if (models_for(quantity, "micrograin").empty() && models_for(quantity, "slab").empty() && models_for(quantity, "spheres").empty())
      throw ConfigError("<python>", "quantity", "\"" + quantity + "\" is predicted by no model of any geometry kind");
    std::vector<py::dict> out;
    for (const ModelInfo& i : models_for(quantity, kind)) {
      py::dict d;
      d["name"] = i.name;
      d["quantity"] = i.quantity;
      d["exact"] = i.exact;
      d["description"] = i.description;
      d["kind"] = i.kind;
      d["component"] = i.component;
      out.push_back(d);
    }
    return out;
  }, py::arg("quantity"), py::arg("kind") = "micrograin", "The suite models of a table quantity for a geometry kind (empty if none of that kind;\n"
        "a quantity no model of any kind predicts, or an unknown kind, is a ConfigError).");

  m.def("evaluate_model", [](const std::string& model, const Table& table, py::object config, bool return_accuracy) {
    const auto [text, file] = config_text(config);
    const Experiment ex = parse_experiment(text, file);
    check_table_layout(ex, table, "<python>", "table");
    std::vector<double> v;
    ModelAccuracy accuracy;
    {
      py::gil_scoped_release release;
      const ModelAccuracyScope scope(&accuracy);
      try {
        v = evaluate_model(model, table, ex);
      } catch (const std::invalid_argument& e) {
        throw ConfigError("<python>", "model", e.what());
      }
    }
    std::vector<py::ssize_t> shape;
    for (std::size_t s : table.shape()) shape.push_back(static_cast<py::ssize_t>(s));
    py::array_t<double> a(shape);
    std::copy(v.begin(), v.end(), a.mutable_data());
    if (!return_accuracy) return py::object(a);
    py::object info = py::none();
    if (accuracy.integrals > 0) {  // as results.json's rule_accuracy
      py::dict d;
      d["target"] = accuracy.target;
      d["integrals"] = accuracy.integrals;
      d["unconverged"] = accuracy.unconverged;
      d["worst_rel_error"] = accuracy.worst_error;
      d["worst_cell"] = accuracy.worst_cell;
      info = d;
    }
    return py::object(py::make_tuple(a, info));
  }, py::arg("model"), py::arg("table"), py::arg("config"), py::arg("return_accuracy") = false,
        "A suite model (e.g. 'tau_plus_eq22', 'ndf_eq17', 'spongecake_ss_brdf', 'deon_corrected')\n"
        "on the cells of a table, as `mcref validate` evaluates it: bin averages over binned\n"
        "axes, point values on point axes. config: the experiment (dict or TOML text), e.g.\n"
        "tables.provenance['config']. Returns an array of the table's shape; with\n"
        "return_accuracy=True, (array, accuracy): accuracy is None for models evaluated by\n"
        "fixed rules, else the adaptive cell rule's record as in results.json's rule_accuracy\n"
        "(target, integrals, unconverged, worst_rel_error, worst_cell: a flat index into the array).");
}

}  // namespace mcref::python
