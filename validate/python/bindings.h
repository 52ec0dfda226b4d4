#pragma once
// The Python module `mcref` (pybind11): one file per concept, each adding its
// functions to the module. Directions are given by angles (theta from the macro
// normal z, phi the azimuth), in radians; see the docstrings.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>


#include "models/core/vec.h"

namespace mcref::python {

namespace py = pybind11;

// Directions are built with spherical_direction(theta, phi) (models/core/vec.h).
// Model functions are wrapped with py::vectorize: every double argument
// broadcasts over numpy arrays; a call on scalars returns a float.

// py::vectorize(f) applied to Python objects (arrays or scalars), for model
// functions that capture non-numeric arguments (a stack of layers, a
// micro-BRDF) converted once per call.
template <typename F, typename... O>
py::object vectorized(F&& f, const O&... objects) {
  return py::vectorize(std::forward<F>(f))(py::array_t<double, py::array::forcecast>::ensure(objects)...);
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
