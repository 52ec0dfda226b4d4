// mcref.sggx: the SGGX microflake distribution (Heitz et al. 2015) and
// SpongeCake single scattering (Wang et al. 2022), vectorised over directions;
// suite models spongecake_ss_brdf / _btdf / _substrate.
#include <cmath>

#include "models/sggx/flake_phase.h"
#include "models/sggx/hg_phase.h"
#include "models/sggx/layer.h"
#include "models/sggx/sggx_distribution.h"
#include "models/sggx/single_scattering.h"
#include "sim/experiment/config_error.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace {

Vec3 vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

// A direction given as a vector (normalised by the factories): finite, not zero.
Vec3 axis_vector(const char* name, const std::array<double, 3>& v) {
  const Vec3 a = vec3(v);
  if (!(std::isfinite(dot(a, a)) && dot(a, a) > 0)) throw ConfigError("<python>", name, "must be a finite, non-zero vector");
  return a;
}

const Range kG{-1, 1, true, true};  // Henyey-Greenstein asymmetry

// What every layer takes, checked with the value shown (thickness may be infinite: a half-space).
void check_layer(double thickness, double density, double albedo) {
  if (!(thickness >= 0))
    throw ConfigError("<python>", "thickness", "= " + exact_text(thickness) + " must be >= 0 (inf: a half-space)");
  check_argument("density", density, {0, INFINITY, false, true});
  check_argument("albedo", albedo, kUnitInterval);
}

// Model factories throw std::invalid_argument: one line for Python too.
template <class F>
auto checked(const std::string& key, F f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw ConfigError("<python>", key, e.what());
  }
}

}  // namespace

void bind_sggx(py::module_& root) {
  py::module_ m = root.def_submodule(
      "sggx",
      "SGGX microflakes (Heitz, Dupuy, Crassin, Dachsbacher 2015) and SpongeCake single scattering\n"
      "(Wang, Jin, Hasan, Yan 2022). Directions as (theta, phi) in radians, z the macro normal;\n"
      "wi toward the light, wo toward the receiver, both away from the surface/scattering point.\n"
      "theta_o > pi/2 is below the stack (transmission). BSDFs in 1/sr WITHOUT the cosine.");

  py::class_<sggx::Sggx>(m, "Sggx", "An SGGX matrix S (symmetric positive definite).")
      .def_static("surface_like", [](double alpha, std::array<double, 3> wp) {
        const Vec3 w = axis_vector("wp", wp);
        return checked("alpha", [&] { return sggx::surface_like(alpha, w); });
      }, py::arg("alpha"), py::arg("wp") = std::array<double, 3>{0, 0, 1},
                  "S = a^2 I + (1 - a^2) wp wp^T: flakes with normals around +-wp.")
      .def_static("fiber_like", [](double alpha, std::array<double, 3> wp) {
        const Vec3 w = axis_vector("wp", wp);
        return checked("alpha", [&] { return sggx::fiber_like(alpha, w); });
      }, py::arg("alpha"), py::arg("wp") = std::array<double, 3>{0, 0, 1},
                  "S = I + (a^2 - 1) wp wp^T: fibres along wp.")
      .def_static("from_matrix", [](std::array<std::array<double, 3>, 3> s) {
        sggx::Mat3 a;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) a(r, c) = s[r][c];
        return checked("S", [&] { return sggx::from_matrix(a); });
      }, py::arg("S"))
      .def_property_readonly("S", [](const sggx::Sggx& s) {
        std::array<std::array<double, 3>, 3> a;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) a[r][c] = s.S(r, c);
        return a;
      });

  m.def("ndf", [](const sggx::Sggx& s, py::object theta_m, py::object phi_m) {
          return vectorized([&](double theta_m, double phi_m) {
          return sggx::ndf(s, spherical_direction(theta_m, phi_m));
        }, theta_m, phi_m);
        }, py::arg("sggx"), py::arg("theta_m"), py::arg("phi_m"),
        "Heitz 2015 Eq. 9 (SpongeCake Eq. 7, general form): D(m) = 1 / (pi sqrt(det S) (m^T S^-1 m)^2).\n"
        "Symmetric; normalised so that the integral of <w.m>+ D over the sphere is sigma(w).");
  m.def("sigma", [](const sggx::Sggx& s, py::object theta, py::object phi) {
          return vectorized([&](double theta, double phi) {
          return sggx::projected_area(s, spherical_direction(theta, phi));
        }, theta, phi);
        }, py::arg("sggx"), py::arg("theta"), py::arg("phi"), "SpongeCake Eq. 3: sigma(w) = sqrt(w^T S w).");
  m.def("visible_ndf", [](const sggx::Sggx& s, py::object tw, py::object pw, py::object tm, py::object pm) {
          return vectorized([&](double tw, double pw, double tm, double pm) {
          return sggx::visible_ndf(s, spherical_direction(tw, pw), spherical_direction(tm, pm));
        }, tw, pw, tm, pm);
        }, py::arg("sggx"), py::arg("theta_w"), py::arg("phi_w"), py::arg("theta_m"), py::arg("phi_m"),
        "<w.m>+ D(m) / sigma(w), per unit solid angle of m.");
  m.def("specular_flake_phase", [](const sggx::Sggx& s, py::object ti, py::object pi_, py::object to, py::object po) {
          return vectorized([&](double ti, double pi_, double to, double po) {
          return sggx::specular_flake_phase(s, spherical_direction(ti, pi_), spherical_direction(to, po));
        }, ti, pi_, to, po);
        }, py::arg("sggx"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"), py::arg("phi_o"),
        "SpongeCake Eq. 4: f_p(wi -> wo) = D(h) / (4 sigma(wi)), h = normalize(wi + wo); normalised.");
  m.def("hg_phase", py::vectorize([](double g, double ti, double pi_, double to, double po) {
          return sggx::hg_phase(argument("g", g, kG), spherical_direction(ti, pi_), spherical_direction(to, po));
        }), py::arg("g"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"), py::arg("phi_o"),
        "Henyey-Greenstein, cos = dot(-wi, wo): (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5).");

  py::class_<sggx::Layer>(m, "Layer", "One homogeneous SpongeCake layer, one colour channel.")
      .def_static("sggx", [](double thickness, double density, const sggx::Sggx& s, double albedo, double f0) {
        check_layer(thickness, density, albedo);
        check_argument("f0", f0, kUnitInterval);
        return checked("layer", [&] { return sggx::sggx_layer(thickness, density, s, albedo, f0); });
      }, py::arg("thickness"), py::arg("density"), py::arg("sggx"), py::arg("albedo") = 1.0, py::arg("f0") = 1.0,
                  "Specular SGGX flakes, F = albedo Schlick(f0, |wi.h|); extinction density sigma(w).")
      .def_static("hg", [](double thickness, double density, double g, double albedo) {
        check_layer(thickness, density, albedo);
        check_argument("g", g, kG);
        return checked("layer", [&] { return sggx::hg_layer(thickness, density, g, albedo); });
      }, py::arg("thickness"), py::arg("density"), py::arg("g"), py::arg("albedo") = 1.0)
      .def_static("isotropic", [](double thickness, double density, double albedo) {
        check_layer(thickness, density, albedo);
        return checked("layer", [&] { return sggx::isotropic_layer(thickness, density, albedo); });
      }, py::arg("thickness"), py::arg("density"), py::arg("albedo") = 1.0)
      .def_property_readonly("optical_thickness", &sggx::Layer::optical_thickness);

  using Stack = std::vector<sggx::Layer>;
  m.def("spongecake_ss_brdf", [](const Stack& st, py::object ti, py::object pi_, py::object to, py::object po) {
          return vectorized([&](double ti, double pi_, double to, double po) {
          return sggx::single_scattering_reflection(st, spherical_direction(ti, pi_), spherical_direction(to, po));
        }, ti, pi_, to, po);
        }, py::arg("layers"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"), py::arg("phi_o"),
        "SpongeCake Eq. 8-12, layers Sec. 4.4: single-scattering reflection of a stack (listed from\n"
        "the top), each lobe attenuated by the layers crossed. 0 if wi, wo are on opposite sides.");
  m.def("spongecake_ss_btdf", [](const Stack& st, py::object ti, py::object pi_, py::object to, py::object po) {
          return vectorized([&](double ti, double pi_, double to, double po) {
          return sggx::single_scattering_transmission(st, spherical_direction(ti, pi_), spherical_direction(to, po));
        }, ti, pi_, to, po);
        }, py::arg("layers"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"), py::arg("phi_o"),
        "SpongeCake Eq. 15-16 with |cos| Lambdas: single-scattering transmission (theta_o > pi/2).");
  m.def("spongecake_ss_substrate", [](const Stack& st, py::object albedo, py::object ti, py::object pi_, py::object to, py::object po) {
          return vectorized([&](double albedo, double ti, double pi_, double to,
                                                    double po) {
          const Vec3 wi = spherical_direction(ti, pi_), wo = spherical_direction(to, po);
          return sggx::single_scattering_reflection(st, wi, wo) +
                 sggx::lambertian_substrate_term(st, wi, wo, argument("substrate_albedo", albedo, kUnitInterval));
        }, albedo, ti, pi_, to, po);
        }, py::arg("layers"), py::arg("substrate_albedo"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"),
        py::arg("phi_o"),
        "Single scattering of the layers + a Lambertian substrate (albedo/pi) seen through the stack\n"
        "(Sec. 4.5): the reflection of a max_order = 1 run.");
  m.def("delta_transmittance", [](const Stack& st, py::object theta, py::object phi) {
          return vectorized([&](double theta, double phi) {
          return sggx::delta_transmittance(st, spherical_direction(theta, phi));
        }, theta, phi);
        }, py::arg("layers"), py::arg("theta"), py::arg("phi"),
        "Unscattered transmittance exp(-sum_k T_k rho_k sigma_k(w) / |w.z|) (Sec. 4.5).");
  m.def("reflection_G", py::vectorize(&sggx::reflection_G), py::arg("tau"), py::arg("lambda_i"), py::arg("lambda_o"),
        "Eq. 12: (1 - exp(-tau (Li + Lo))) / (Li + Lo).");
  m.def("transmission_G", py::vectorize(&sggx::transmission_G), py::arg("tau"), py::arg("lambda_i"), py::arg("lambda_o"),
        "Eq. 16 with |cos|: (exp(-tau Lo) - exp(-tau Li)) / (Li - Lo).");
}

}  // namespace mcref::python
