// mcref.radiative_transfer: Chandrasekhar's isotropic half-space (H-function
// and BRDFs), vectorised. Suite model: chandrasekhar_isotropic.
#include "models/radiative_transfer/isotropic.h"
#include "sim/experiment/config_error.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace rt = radiative_transfer;

namespace {
// The albedo in [0, 1] (outside it H is not defined; Fock's integral still gives numbers).
double albedo_in(double albedo) { return argument("albedo", albedo, kUnitInterval); }
}  // namespace

void bind_radiative_transfer(py::module_& root) {
  py::module_ m = root.def_submodule(
      "radiative_transfer",
      "Isotropic scattering in a semi-infinite medium (Chandrasekhar 1960). albedo in [0, 1];\n"
      "mu_i, mu_o cosines of directions pointing away from the surface; BRDFs in 1/sr WITHOUT\n"
      "the cosine, independent of the azimuth.");
  m.def("h_isotropic", py::vectorize([](double a, double mu) { return rt::h_isotropic(albedo_in(a), argument("mu", mu, kUnitInterval)); }), py::arg("albedo"), py::arg("mu"),
        "Chandrasekhar's H(mu) for isotropic scattering by Fock's integral (d'Eon Eq. 16),\n"
        "|error| < 1e-12; H(1) = 2.9078105 at albedo 1. ~0.2 ms per value (see h_isotropic_table).");
  m.def("h_isotropic_table", [](double albedo, py::object mu) {
          albedo_in(albedo);
          const rt::HTable h = rt::isotropic_h_table(albedo);
          return py::vectorize([&](double x) { return h(argument("mu", x, kUnitInterval)); })(numbers(mu));
        }, py::arg("albedo"), py::arg("mu"), "H(mu) for one albedo, tabulated once (|rel. error| < 1e-13), ~0.5 us per value.");
  m.def("chandrasekhar_isotropic", py::vectorize([](double a, double mi, double mo) {
          return rt::brdf_isotropic(albedo_in(a), argument("mu_i", mi, kUnitInterval), argument("mu_o", mo, kUnitInterval));
        }), py::arg("albedo"), py::arg("mu_i"), py::arg("mu_o"),
        "All orders (suite model chandrasekhar_isotropic): albedo H(mu_i) H(mu_o) / (4 pi (mu_i + mu_o)).");
  m.def("single_scattering_isotropic", py::vectorize([](double a, double mi, double mo) {
          return rt::single_scattering_brdf_isotropic(albedo_in(a), argument("mu_i", mi, kUnitInterval),
                                                      argument("mu_o", mo, kUnitInterval));
        }), py::arg("albedo"),
        py::arg("mu_i"), py::arg("mu_o"), "Single scattering: albedo / (4 pi (mu_i + mu_o)).");
}

}  // namespace mcref::python
