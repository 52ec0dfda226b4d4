// Tables in Python: mcref.Table / Axis / TableFile, read_tables, write_tables,
// and judge (a table against a model's values, as `mcref validate` judges).
// Arrays are copies (numpy, float64, row-major in the table's axis order);
// files go through the C++ writer (temporary file renamed into place).
#include <cmath>
#include <stdexcept>

#include "sim/experiment/config_error.h"
#include "sim/files/output_path.h"
#include "sim/hdf5/table_file.h"
#include "sim/hdf5/table_group.h"
#include "validate/metrics.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A copy of the table's data, read-only: writing into it would change nothing
// in the table, so numpy refuses it (ValueError) instead of losing it.
py::array_t<double> shaped(const Table& t, const std::vector<double>& v) {
  std::vector<py::ssize_t> shape;
  for (std::size_t s : t.shape()) shape.push_back(static_cast<py::ssize_t>(s));
  py::array_t<double> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// The kept batch values, shaped (batches,) + the table's shape, read-only as `shaped`.
py::array_t<double> batch_array(const Table& t) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(t.batches)};
  for (std::size_t s : t.shape()) shape.push_back(static_cast<py::ssize_t>(s));
  py::array_t<double> a(shape);
  std::copy(t.batch_values.begin(), t.batch_values.end(), a.mutable_data());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

std::vector<double> flat(const Table& t, const Array& a, const char* what) {
  const std::vector<std::size_t> shape = t.shape();
  bool ok = static_cast<std::size_t>(a.ndim()) == shape.size();
  for (std::size_t k = 0; ok && k < shape.size(); ++k) ok = static_cast<std::size_t>(a.shape(k)) == shape[k];
  if (!ok) throw ConfigError("table " + t.name, what, "shape does not match the table's axes");
  return std::vector<double>(a.data(), a.data() + a.size());
}

py::dict provenance_dict(const Provenance& p) {
  py::dict d;
  d["mcref_version"] = p.mcref_version;
  d["git_commit"] = p.git_commit;
  d["sim_fingerprint"] = p.sim_fingerprint;
  d["created"] = p.created;
  d["command_line"] = p.command_line;
  d["config"] = p.config;
  d["source_file"] = p.source_file;
  d["seed"] = p.seed;
  return d;
}

const Table& find_table(const TableFile& f, const std::string& name) {
  const Table* t = f.find(name);
  if (!t) {
    std::string names;
    for (const Table& x : f.tables) names += (names.empty() ? "" : ", ") + x.name;
    throw py::key_error("no table '" + name + "' (tables: " + names + ")");
  }
  return *t;
}

}  // namespace

void bind_tables(py::module_& m) {
  py::class_<Axis>(m, "Axis", "One axis of a table: bins (edges) or points.")
      .def_static("bins", &Axis::bins, py::arg("name"), py::arg("unit"), py::arg("edges"))
      .def_static("points", &Axis::points, py::arg("name"), py::arg("unit"), py::arg("values"))
      .def_readonly("name", &Axis::name)
      .def_readonly("unit", &Axis::unit)
      .def_property_readonly("kind", [](const Axis& a) { return a.kind == Axis::Kind::Bins ? "bins" : "points"; })
      .def_property_readonly("centres", [](const Axis& a) {
        std::vector<double> c(a.size());
        for (std::size_t i = 0; i < c.size(); ++i) c[i] = a.centre(i);
        return py::array_t<double>(c.size(), c.data());
      }, "bin centres, or the points")
      .def_property_readonly("edges", [](const Axis& a) -> py::object {
        if (a.kind != Axis::Kind::Bins) return py::none();
        return py::array_t<double>(a.values.size(), a.values.data());
      }, "bin edges (None for a point axis)")
      .def("__len__", &Axis::size)
      .def("__repr__", [](const Axis& a) {
        return "<mcref.Axis " + a.name + " [" + a.unit + "] " + std::to_string(a.size()) +
               (a.kind == Axis::Kind::Bins ? " bins>" : " points>");
      });

  py::class_<Table>(m, "Table",
                    "A table of per-batch estimates: sum and sum_sq over batches per cell.\n"
                    "value = sum / batches; stderr = sample standard deviation / sqrt(batches).")
      .def(py::init([](std::string name, std::string quantity, std::vector<Axis> axes, Array sum, Array sum_sq,
                       std::int64_t batches, std::string units, std::string description,
                       std::map<std::string, std::string> attributes) {
             Table t(std::move(name), std::move(quantity), std::move(axes));
             t.sum = flat(t, sum, "sum");
             t.sum_sq = flat(t, sum_sq, "sum_sq");
             if (batches < 1) throw ConfigError("table " + t.name, "batches", "must be at least 1");
             t.batches = batches;
             t.units = std::move(units);
             t.description = std::move(description);
             t.attributes = std::move(attributes);
             return t;
           }),
           py::arg("name"), py::arg("quantity"), py::arg("axes"), py::arg("sum"), py::arg("sum_sq"),
           py::arg("batches"), py::arg("units") = "", py::arg("description") = "",
           py::arg("attributes") = std::map<std::string, std::string>{})
      .def_readonly("name", &Table::name)
      .def_readonly("quantity", &Table::quantity)
      .def_readonly("units", &Table::units)
      .def_readonly("description", &Table::description)
      .def_readonly("batches", &Table::batches)
      .def_readonly("attributes", &Table::attributes)
      .def_readonly("axes", &Table::axes)
      .def_property_readonly("axis_names", [](const Table& t) {
        std::vector<std::string> n;
        for (const Axis& a : t.axes) n.push_back(a.name);
        return n;
      })
      .def("axis", [](const Table& t, const std::string& name) {
        for (const Axis& a : t.axes)
          if (a.name == name) return a;
        throw py::key_error("table " + t.name + " has no axis '" + name + "'");
      })
      .def_property_readonly("shape", &Table::shape)
      .def_property_readonly("value", [](const Table& t) { return shaped(t, t.values()); })
      .def_property_readonly("stderr", [](const Table& t) { return shaped(t, t.stderrs()); })
      .def_property_readonly("sum", [](const Table& t) { return shaped(t, t.sum); })
      .def_property_readonly("sum_sq", [](const Table& t) { return shaped(t, t.sum_sq); })
      .def_property_readonly("batch_values", [](const Table& t) -> py::object {
        if (!t.has_batch_values()) return py::none();
        return batch_array(t);
      }, "Each batch's estimates, shape (batches,) + shape, or None if the table did not keep them\n"
         "(simulate(..., keep_batch_values=True), and mcref validate's tables, keep them).")
      .def("to_xarray", [](const Table& t) {
        py::module_ xr = py::module_::import("xarray");  // optional: ImportError without it
        py::list dims;
        py::dict coords, data, attrs;
        for (const Axis& a : t.axes) {
          dims.append(a.name);
          std::vector<double> c(a.size());
          for (std::size_t i = 0; i < c.size(); ++i) c[i] = a.centre(i);
          // The netCDF-CF names of the file (sim/hdf5/table_file.h).
          py::dict axis_attrs(py::arg("units") = a.unit);
          if (a.kind == Axis::Kind::Bins) {
            axis_attrs["bounds"] = a.name + "_bounds";
            py::array_t<double> b({a.size(), std::size_t{2}});
            for (std::size_t i = 0; i < a.size(); ++i) {
              b.mutable_at(i, 0) = a.lower(i);
              b.mutable_at(i, 1) = a.upper(i);
            }
            coords[py::str(a.name + "_bounds")] = py::make_tuple(py::make_tuple(a.name, "bnds"), b, py::dict(py::arg("units") = a.unit));
          }
          coords[py::str(a.name)] = py::make_tuple(a.name, py::array_t<double>(c.size(), c.data()), axis_attrs);
          const std::vector<std::string> labels = axis_labels(t, a);
          if (!labels.empty()) coords[py::str(a.name + "_label")] = py::make_tuple(a.name, labels);
        }
        py::tuple d = py::tuple(dims);
        const py::dict units(py::arg("units") = t.units);
        data["value"] = py::make_tuple(d, shaped(t, t.values()), units);
        data["stderr"] = py::make_tuple(d, shaped(t, t.stderrs()), units);
        data["sum"] = py::make_tuple(d, shaped(t, t.sum), units);
        data["sum_sq"] = py::make_tuple(d, shaped(t, t.sum_sq));
        if (t.has_batch_values() && t.batches > 0) {  // as the file's batch_values, over the batch dimension
          py::list batch_dims;
          batch_dims.append("batch");
          for (const auto& n : dims) batch_dims.append(n);
          std::vector<double> index(static_cast<std::size_t>(t.batches));
          for (std::size_t b = 0; b < index.size(); ++b) index[b] = static_cast<double>(b);
          coords["batch"] = py::make_tuple("batch", py::array_t<double>(index.size(), index.data()), py::dict(py::arg("units") = "1"));
          data["batch_values"] = py::make_tuple(py::tuple(batch_dims), batch_array(t), units);
        }
        attrs["name"] = t.name;
        attrs["quantity"] = t.quantity;
        attrs["units"] = t.units;
        attrs["description"] = t.description;
        attrs["batches"] = t.batches;
        for (const auto& [k, v] : t.attributes) attrs[py::str(k)] = v;
        return xr.attr("Dataset")(data, py::arg("coords") = coords, py::arg("attrs") = attrs);
      }, "The table as an xarray.Dataset (value, stderr, sum, sum_sq over the axes, and batch_values over\n"
         "batch and the axes if kept; needs xarray).")
      .def("__repr__", [](const Table& t) {
        std::string s = "<mcref.Table " + t.name + " (" + t.quantity + ", " + t.units + "), axes";
        for (const Axis& a : t.axes) s += " " + a.name + "[" + std::to_string(a.size()) + "]";
        return s + ", " + std::to_string(t.batches) + " batches>";
      });

  py::class_<TableFile>(m, "TableFile", "The tables of one file (or one simulation) with their provenance.")
      .def_readonly("tables", &TableFile::tables)
      .def_property_readonly("provenance", [](const TableFile& f) { return provenance_dict(f.provenance); })
      .def_property_readonly("names", [](const TableFile& f) {
        std::vector<std::string> n;
        for (const Table& t : f.tables) n.push_back(t.name);
        return n;
      })
      .def("__getitem__", &find_table, py::return_value_policy::copy)
      .def("__contains__", [](const TableFile& f, const std::string& name) { return f.find(name) != nullptr; })
      .def("__len__", [](const TableFile& f) { return f.tables.size(); })
      .def("__iter__", [](const TableFile& f) {  // the names, as a dict's keys (`in` and [name] take names)
        std::vector<std::string> n;
        for (const Table& t : f.tables) n.push_back(t.name);
        return py::iter(py::cast(n));
      })
      .def("__repr__", [](const TableFile& f) {
        std::string s = "<mcref.TableFile:";
        for (const Table& t : f.tables) s += " " + t.name;
        return s + ">";
      });

  m.def("read_tables", [](const std::filesystem::path& p) {
    const std::string path = p.string();
    py::gil_scoped_release release;
    return read_table_file(path);
  }, py::arg("path"), "Reads an mcref table file (HDF5). Raises ConfigError for a file mcref did not write.");

  m.def("write_tables", [](const std::filesystem::path& p, const TableFile& file) {
    const std::string path = p.string();
    // Never onto the experiment file the tables came from (as the CLI's -o).
    const std::string& source = file.provenance.source_file;
    check_output_file(path, source.empty() || source.front() == '<' ? std::vector<std::string>{} : std::vector{source},
                      "path");
    py::gil_scoped_release release;
    write_table_file(path, file);
  }, py::arg("path"), py::arg("tables"),
        "Writes a TableFile (from simulate or read_tables) to an HDF5 file that `mcref info` and\n"
        "`mcref validate` read; written to a temporary name and renamed, never half-written.");

  m.def("write_tables", [](const std::filesystem::path& p, const std::vector<Table>& tables, const std::string& config,
                           py::object seed, const std::string& command_line) {
    const std::string path = p.string();
    check_output_file(path, {}, "path");
    TableFile f;
    f.tables = tables;
    f.provenance = make_provenance(config, "<python>", integer_argument("seed", seed, UINT64_MAX), command_line);
    py::gil_scoped_release release;
    write_table_file(path, f);
  }, py::arg("path"), py::arg("tables"), py::arg("config") = "", py::arg("seed") = py::int_(0),
        py::arg("command_line") = "python: mcref.write_tables",
        "Writes a list of Tables with new provenance (config text, seed, this mcref build, now).");

  m.def("judge", [](const Table& t, const Array& model, bool exact, double significance, double tolerance,
                    py::object model_stderr, bool use_batch_values) {
    check_argument("significance", significance, {0, 1, true, true});
    check_argument("tolerance", tolerance, {0, INFINITY, false, true});
    const std::vector<double> m = flat(t, model, "model");
    const std::vector<double> mse = model_stderr.is_none() ? std::vector<double>{} : flat(t, Array(model_stderr), "model_stderr");
    for (std::size_t i = 0; i < mse.size(); ++i)  // (a negative one passed a model 3x off; NaN was taken as 0)
      if (std::isfinite(m[i]) && !(mse[i] >= 0 && mse[i] < INFINITY))
        throw ConfigError("<python>", "model_stderr", "= " + exact_text(mse[i]) +
                                                          " is out of range where the model is defined; allowed [0, inf)");
    static const std::vector<double> none;
    Comparison c = compare(t.values(), t.stderrs(), m, t.batches, mse, t.channels(),
                           use_batch_values && t.has_batch_values() ? t.batch_values : none);
    const Verdict v = judge(c, exact, significance, tolerance);
    settle_joint_test(c, significance);
    py::dict d;
    d["status"] = v.status;
    d["reason"] = v.reason;
    d["cells"] = c.cells;
    d["chi2_per_dof"] = c.chi2_per_dof();
    d["p_value"] = c.p_value;
    d["effective_dof"] = c.effective_dof;
    d["joint_test"] = c.joint_test;
    d["max_abs_z"] = c.max_abs_z;
    d["max_rel_error"] = c.max_rel_error;
    d["rms_rel_error"] = c.rms_rel_error;
    d["z"] = shaped(t, c.z);
    return d;
  }, py::arg("table"), py::arg("model"), py::arg("exact") = true, py::arg("significance") = 1e-3,
        py::arg("tolerance") = 0.0, py::arg("model_stderr") = py::none(), py::arg("use_batch_values") = true,
        "Judges a table against a model's values on its cells, as `mcref validate` does (README:\n"
        "Verdicts): returns a dict with status ('pass', 'FAIL', 'measured' or 'n/a'), reason,\n"
        "cells, chi2_per_dof, p_value, joint_test, effective_dof, max_abs_z,\n"
        "max_rel_error and rms_rel_error (of the model against the table, over cells where\n"
        "|table| > 5 stderr) and z (per cell). exact: judged by the chi2 and |z|\n"
        "tests at `significance`; otherwise measured, or judged on the largest relative error\n"
        "when tolerance > 0. model_stderr: the model's own standard error per cell, if it is a\n"
        "Monte Carlo estimate. With the table's batch values (and use_batch_values), p comes\n"
        "from a sign-flip test over the batches or a chi2 with their correlation (joint_test\n"
        "'sign-flip' or 'Box'); without, from a chi2 with the cells taken as independent.");
}

}  // namespace mcref::python
