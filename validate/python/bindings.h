#pragma once
// The Python module `mcref` (pybind11): one file per concept, each adding its
// functions to the module. Directions are given by angles (theta from the macro
// normal z, phi the azimuth), in radians; see the docstrings.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>  // paths: str or os.PathLike (pathlib.Path)

#include <cmath>
#include <cstdint>
#include <string>

#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/toml_reader.h"

namespace mcref::python {

namespace py = pybind11;

// Directions are built with spherical_direction(theta, phi) (models/core/vec.h).
// Model functions are wrapped with py::vectorize: every double argument
// broadcasts over numpy arrays; a call on scalars returns a float.

using Numbers = py::array_t<double, py::array::forcecast>;

// An argument as an array of doubles; anything that is not numbers (a string,
// a list holding one) is a TypeError. (ensure() returns a null array then,
// which py::vectorize would dereference.)
inline Numbers numbers(const py::handle& o) {
  Numbers a = Numbers::ensure(o);
  if (!a)
    throw py::type_error("expected a number or an array of numbers, got " + std::string(py::str(py::repr(o))));
  return a;
}

// py::vectorize(f) applied to Python objects (arrays or scalars), for model
// functions that capture non-numeric arguments (a stack of layers, a
// micro-BRDF) converted once per call.
template <typename F, typename... O>
py::object vectorized(F&& f, const O&... objects) {
  return py::vectorize(std::forward<F>(f))(numbers(objects)...);
}

// A non-negative integer argument (a Python or numpy integer) at most `hi`; a
// float, a bool or anything out of range is a ConfigError naming the argument.
inline std::uint64_t integer_argument(const char* name, const py::handle& v, std::uint64_t hi) {
  const auto fail = [&] {
    return ConfigError("<python>", name, "= " + std::string(py::repr(v)) + " must be an integer in [0, " + std::to_string(hi) + "]");
  };
  if (py::isinstance<py::bool_>(v) || !PyIndex_Check(v.ptr())) throw fail();
  const py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
  if (!i) throw py::error_already_set();
  const unsigned long long x = PyLong_AsUnsignedLongLong(i.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    throw fail();
  }
  if (x > hi) throw fail();
  return x;
}

// A whole number in [lo, hi] given where numbers broadcast (py::vectorize
// would truncate 4.7 to 4): a ConfigError naming the argument otherwise.
inline int whole_argument(const char* name, double value, int lo, int hi) {
  if (!(value >= lo && value <= hi && value == static_cast<int>(value)))
    throw ConfigError("<python>", name, "= " + exact_text(value) + " must be a whole number in [" + std::to_string(lo) + ", " +
                                            std::to_string(hi) + "]");
  return static_cast<int>(value);
}

// A scalar argument checked against its allowed range: a ConfigError naming
// the argument, its value (every digit) and the range, as the CLI's.
inline void check_argument(const char* name, double value, const Range& allowed) {
  if (!allowed.contains(value))
    throw ConfigError("<python>", name, "= " + exact_text(value) + " is out of range; allowed " + allowed.text());
}

// A value checked as check_argument, returned: for arguments that broadcast
// (checked per element inside py::vectorize).
inline double argument(const char* name, double value, const Range& allowed) {
  check_argument(name, value, allowed);
  return value;
}
// Ranges shared by the model families.
inline const Range kUnitInterval{0, 1, false, false};  // albedos, cosines away from the surface, heights
inline const Range kCosine{-1, 1, false, false};       // a cosine between two directions

// A micrograin field's parameters in the models' domain, tau0 in (0, 1) and
// beta > 0 (outside it the formulas still give numbers, e.g. tau+ < 0 for tau0 < 0).
inline double tau0_in(double tau0) {
  check_argument("tau0", tau0, {0, 1, true, true});
  return tau0;
}
inline double beta_in(double beta, const char* name = "beta") {
  check_argument(name, beta, {0, INFINITY, true, true});
  return beta;
}
// The field of (tau0, beta_x, beta_y), checked.
inline micrograin::GrainField grain_field(double tau0, double bx, double by) {
  return {tau0_in(tau0), beta_in(bx, "beta_x"), beta_in(by, "beta_y")};
}

void bind_tables(py::module_& m);        // Table, read_tables, write_tables
void bind_simulate(py::module_& m);      // simulate, evaluate_model
void bind_micrograin(py::module_& m);    // micrograin models (LRPB23, vNDF paper)
void bind_sggx(py::module_& m);          // SGGX and SpongeCake
void bind_spongecake_lobes(py::module_& m);  // SpongeCake multiple-scattering lobes (after bind_sggx)
void bind_lambert_sphere(py::module_& m);  // d'Eon 2021
void bind_radiative_transfer(py::module_& m);  // Chandrasekhar's H
void bind_samplers(py::module_& m);      // samplers returning (samples, pdf)

}  // namespace mcref::python
