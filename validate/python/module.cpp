// The Python module `mcref`: tables, simulation and the analytic models.
#include <hdf5.h>

#include "sim/experiment/config_error.h"
#include "sim/files/temp_file.h"
#include "validate/python/bindings.h"

PYBIND11_MODULE(mcref, m) {
  // As in the CLI (validate/app/main.cpp): every file is closed explicitly.
  H5dont_atexit();
  // Python's signal handlers stay (Ctrl-C raises KeyboardInterrupt; a write's
  // temporary is removed by its destructor): sim/files/temp_file.h.
  mcref::leave_signals_to_host();
  m.doc() =
      "mcref: Monte Carlo ground truth for analytic BRDF models of porous microstructures.\n"
      "\n"
      "Conventions (DESIGN.md): z is the macro normal; directions point away from the\n"
      "surface and are given as polar angle theta (from z) and azimuth phi, in radians;\n"
      "relative azimuth phi = phi_o - phi_i, 0 back toward the light, pi the mirror side;\n"
      "BRDF values f_r in 1/sr WITHOUT the cosine. Model functions broadcast numpy\n"
      "arrays (and scalars) over their numeric arguments.";
  // Bad input raises mcref.ConfigError (a ValueError) with the CLI's one-line message.
  static pybind11::exception<mcref::ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const mcref::ConfigError& e) {
      config_error(e.what());
    }
  });
  mcref::python::bind_tables(m);
  mcref::python::bind_simulate(m);
  mcref::python::bind_micrograin(m);
  mcref::python::bind_sggx(m);
  mcref::python::bind_spongecake_lobes(m);
  mcref::python::bind_lambert_sphere(m);
  mcref::python::bind_radiative_transfer(m);
  mcref::python::bind_samplers(m);
}
