// mcref.lambert_sphere: d'Eon 2021, "An analytic BRDF for materials with
// spherical Lambertian scatterers" (half-space BRDFs), vectorised; names follow the
// suite models (validate/spheres/sphere_models.cpp).
// BRDFs: 1/sr WITHOUT the cosine; mu_i, mu_o the cosines of omega_i, omega_o
// (both away from the surface); phi = phi_o - phi_i, 0 back toward the light.
#include <memory>

#include "models/lambert_sphere/albedo_mapping.h"
#include "models/lambert_sphere/brdf.h"
#include "models/lambert_sphere/fast_brdf.h"
#include "models/lambert_sphere/fourier_modes.h"
#include "models/lambert_sphere/h_functions.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/reference_brdf.h"
#include "models/lambert_sphere/single_scattering.h"
#include "sim/experiment/config_error.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace ls = lambert_sphere;

namespace {


// The suite's d'Eon variants (validate/spheres/sphere_models.cpp, make_deon).
ls::BrdfOptions deon_options(const std::string& variant, double& c) {
  ls::BrdfOptions o;
  auto exact = [&](ls::FirstModeVariant v) {
    o.first_mode = v;
    o.h1 = ls::H1Source::exact;
    o.exact_h0 = true;
    o.exact_constants = true;
    c = std::min(c, 0.9999);  // exact constants need c < 1 (as the suite)
  };
  if (variant == "deon_published") {
  } else if (variant == "deon_corrected") {
    o.first_mode = ls::FirstModeVariant::corrected;
    o.h1 = ls::H1Source::log_separable_fit;
  } else if (variant == "deon_corrected_h1_printed") {
    o.first_mode = ls::FirstModeVariant::corrected;
  } else if (variant == "deon_published_exact_h") {
    exact(ls::FirstModeVariant::published);
  } else if (variant == "deon_corrected_exact_h") {
    exact(ls::FirstModeVariant::corrected);
  } else {
    throw ConfigError("<python>", "variant", "\"" + variant + "\" must be one of deon_published, deon_corrected, "
                      "deon_corrected_h1_printed, deon_published_exact_h, deon_corrected_exact_h");
  }
  return o;
}

void check_albedo(double c, bool open_top) { check_argument("c", c, {0, 1, false, open_top}); }

// Per-element arguments (the models' domain, lambert_sphere/*.h): outside it
// the formulas still give numbers (H-functions have a pole at negative mu).
double c_in(double c) { return argument("c", c, kUnitInterval); }
double mu_in(const char* name, double mu) { return argument(name, mu, kUnitInterval); }

}  // namespace

void bind_lambert_sphere(py::module_& root) {
  py::module_ m = root.def_submodule(
      "lambert_sphere",
      "Lambertian-sphere half-space (d'Eon 2021). c: particle albedo in [0, 1]; mu_i, mu_o:\n"
      "cosines of omega_i, omega_o (both pointing away from the surface); phi = phi_o - phi_i,\n"
      "0 back toward the light, pi the mirror side. BRDFs in 1/sr WITHOUT the cosine.");

  m.def("phase_eq1", py::vectorize([](double mu) { return ls::phase_function(argument("mu", mu, kCosine)); }), py::arg("mu"),
        "Eq. 1: p(mu) = 2 (sqrt(1 - mu^2) - mu acos mu) / (3 pi^2), per steradian; mu the cosine\n"
        "between the incoming propagation direction and the scattered direction (mean -4/9).");
  m.def("phase_three_term", py::vectorize([](double mu) { return ls::phase_function_three_term(argument("mu", mu, kCosine)); }),
        py::arg("mu"),
        "Eq. 7-8 / (4 pi c): (1/4pi)(1 - 4 mu/3 + 5 P_2(mu)/16), per steradian.");
  m.def("single_scattering_eq10",
        py::vectorize([](double c, double mi, double mo, double phi) { return ls::single_scattering(c_in(c), mu_in("mu_i", mi), mu_in("mu_o", mo), phi); }),
        py::arg("c"), py::arg("mu_i"), py::arg("mu_o"), py::arg("phi"),
        "Eq. 10: f1 = c p(-omega_i.omega_o) / (mu_i + mu_o), exact single scattering.");
  m.def("deon_fast_eq41",
        py::vectorize([](double c, double mi, double mo, double phi) { return ls::brdf_fast(c_in(c), mu_in("mu_i", mi), mu_in("mu_o", mo), phi); }),
        py::arg("c"), py::arg("mu_i"), py::arg("mu_o"), py::arg("phi"), "Eq. 41: the fast BRDF (with Eq. 10 and Eq. 40).");
  m.def("deon_brdf", [](double c, py::object mu_i, py::object mu_o, py::object phi, const std::string& variant) {
          check_albedo(c, false);
          double cc = c;
          const ls::BrdfOptions o = deon_options(variant, cc);
          const ls::Brdf brdf(cc, o);
          return py::vectorize([&](double mi, double mo, double ph) { return brdf(mu_in("mu_i", mi), mu_in("mu_o", mo), ph); })(
              numbers(mu_i), numbers(mu_o), numbers(phi));
        }, py::arg("c"), py::arg("mu_i"), py::arg("mu_o"), py::arg("phi"), py::arg("variant") = "deon_published",
        "Eq. 11-12 with Eq. 21: f1 + f_m^(0) (Eq. 38) + f_m^(1) cos phi, one albedo c (scalar), the\n"
        "suite variants: deon_published (Eq. 28, fits Eq. 23-27, 31-37), deon_corrected (2 x Eq. 22 -\n"
        "192 pi term, log-separable H1), deon_corrected_h1_printed, deon_published_exact_h,\n"
        "deon_corrected_exact_h (exact H-functions and constants; c capped at 0.9999).");
  m.def("reference_three_term", [](double c, py::object mu_i, py::object mu_o, py::object phi) {
          check_albedo(c, false);
          const ls::ReferenceBrdf ref(std::min(c, 0.9999), true);
          return py::vectorize([&](double mi, double mo, double ph) { return ref(mu_in("mu_i", mi), mu_in("mu_o", mo), ph); })(
              numbers(mu_i), numbers(mu_o), numbers(phi));
        }, py::arg("c"), py::arg("mu_i"), py::arg("mu_o"), py::arg("phi"),
        "Reference BRDF without fits: Eq. 10 + exact three-term multiple-scattering modes (c capped at 0.9999).");

  // H-functions (Sec. 3.1-3.4)
  m.def("h_exact", py::vectorize([](double order, double c, double mu) { return ls::h_exact(whole_argument("m", order, 0, 2), c_in(c), mu_in("mu", mu)); }),
        py::arg("m"), py::arg("c"), py::arg("mu"), "Exact H^(m)(mu), m = 0, 1, 2, by Fock's integral (Eq. 16-20).");
  m.def("h1_fit", py::vectorize([](double c, double mu) { return ls::h1_fit(c_in(c), mu_in("mu", mu)); }), py::arg("c"), py::arg("mu"), "Eq. 23: H^(1) ~ Eq. 24 x Eq. 25 (as printed).");
  m.def("h1_fit_log_separable",
        py::vectorize([](double c, double mu) { return ls::h1_fit_log_separable(c_in(c), mu_in("mu", mu)); }), py::arg("c"), py::arg("mu"),
        "NOT PUBLISHED: H^(1)(1)^(mu^e(mu)) reading of Eq. 23-25 (within 0.37 % of exact).");
  m.def("h1_fit_conservative", py::vectorize([](double mu) { return ls::h1_fit_conservative(mu_in("mu", mu)); }), py::arg("mu"), "Eq. 24: H^(1) at c = 1.");
  m.def("h1_fit_at_one", py::vectorize([](double c) { return ls::h1_fit_at_one(c_in(c)); }), py::arg("c"), "Eq. 25: H^(1)(1).");
  m.def("h0_fit", py::vectorize([](double c, double mu) { return ls::h0_fit(c_in(c), mu_in("mu", mu)); }), py::arg("c"), py::arg("mu"), "Eq. 31: H^(0)(mu) fit.");
  m.def("h0_at_infinity", py::vectorize([](double c) { return ls::h0_at_infinity(c_in(c)); }), py::arg("c"), "Eq. 32: H^(0)(inf).");

  // Albedo mappings (Sec. 3.5)
  m.def("albedo_from_kd", py::vectorize([](double kd) { return ls::albedo_from_kd(argument("kd", kd, kUnitInterval)); }), py::arg("kd"),
        "Eq. 39: particle albedo c from the spherical albedo k_d.");
  m.def("kd_eq40", py::vectorize([](double c) { return ls::kd_from_albedo(c_in(c)); }), py::arg("c"),
        "Eq. 40 (suite model kd_eq40): spherical albedo k_d from the particle albedo c.");
  m.def("kd_reference_three_term", py::vectorize([](double c) {
          check_albedo(c, true);
          return ls::spherical_albedo_reference(c);
        }), py::arg("c"),
        "k_d of reference_three_term by quadrature (~1 s per value), c in [0, 1).");
}

}  // namespace mcref::python
