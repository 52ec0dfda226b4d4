// mcref.micrograin: the micrograin models of LRPB23 (Lucas et al. 2023) and the
// vNDF paper (LRPB24 as quoted there), vectorised; names follow the suite models.
// Directions: polar angle theta from the macro normal z and azimuth phi, radians.
#include "models/micrograin/closest_grain.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/height_masking.h"
#include "models/micrograin/micrograin_bsdf.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/projected_area.h"
#include "models/micrograin/smith_lambda.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"
#include "models/micrograin/visible_ndf.h"
#include "sim/experiment/config_error.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace mg = micrograin;

namespace {

mg::GrainField iso(double tau0, double beta) { return mg::isotropic_field(tau0_in(tau0), beta_in(beta)); }

const Range kPositive{0, INFINITY, true, true};  // densities, radii, roughness
const Range kLength{0, INFINITY, false, true};   // distances (0 allowed)
// A unit-space height h in [0, 1] (vNDF Eq. 3-5: the cap above h).
double height_in(double h) { return argument("h", h, kUnitInterval); }
// A direction's polar angle from the macro normal, in [0, pi/2] (beyond it the
// formulas give numbers outside their domain: tau_plus_eq22 at 2 rad was -0.63).
double theta_in(const char* name, double theta) { return argument(name, theta, Range{0, kPi / 2, false, false}); }
// An azimuth: any finite angle.
double phi_in(const char* name, double phi) { return argument(name, phi, Range{-INFINITY, INFINITY, true, true}); }
// An upper-hemisphere direction from its checked angles.
Vec3 direction_in(const char* theta_name, double theta, const char* phi_name, double phi) {
  return spherical_direction(theta_in(theta_name, theta), phi_in(phi_name, phi));
}

mg::LambdaMethod lambda_method(const std::string& s) {
  if (s == "series4") return mg::LambdaMethod::Series4;
  if (s == "quadrature") return mg::LambdaMethod::Quadrature;
  if (s == "ggx") return mg::LambdaMethod::GgxEquivalent;
  throw ConfigError("<python>", "lambda", "\"" + s + "\" must be one of series4, quadrature, ggx");
}

mg::MicroSurface::Type surface_type(const std::string& s) {
  using T = mg::MicroSurface::Type;
  if (s == "black") return T::Black;
  if (s == "lambertian") return T::Lambertian;
  if (s == "conductor") return T::Conductor;
  if (s == "rough_conductor") return T::RoughConductor;
  if (s == "diffuse_specular") return T::DiffuseSpecular;
  throw ConfigError("<python>", "type", "\"" + s + "\" must be one of black, lambertian, conductor, rough_conductor, diffuse_specular");
}

}  // namespace

void bind_micrograin(py::module_& root) {
  py::module_ m = root.def_submodule(
      "micrograin",
      "Micrograin models (LRPB23 = Lucas, Ribardiere, Pacanowski, Barla 2023; vNDF = the\n"
      "micrograin visible-NDF paper). Field: filling factor tau0 in (0, 1), slope scale\n"
      "beta = c / r > 0 (beta_x, beta_y for anisotropic fields). Angles in radians; theta\n"
      "from the macro normal z. BSDFs in 1/sr without the cosine. All numeric arguments\n"
      "broadcast over numpy arrays.");

  // LRPB23 Sec. 4.1
  m.def("p1_eq10", py::vectorize([](double r, double rho) {
          return mg::closest_grain_distance_pdf(argument("r", r, kLength), argument("rho", rho, kPositive));
        }), py::arg("r"), py::arg("rho"),
        "LRPB23 Eq. 8 (suite model p1_eq10): p1(r) = 2 pi rho r exp(-pi rho r^2), density of the\n"
        "distance r to the closest grain centre (rho centres per unit area; r in the same unit).");
  m.def("filling_factor", py::vectorize([](double rho, double rx, double ry) {
          return mg::filling_factor(argument("rho", rho, kLength), argument("r_x", rx, kPositive), argument("r_y", ry, kPositive));
        }), py::arg("rho"), py::arg("r_x"), py::arg("r_y"),
        "LRPB23 Eq. 13: tau0 = 1 - exp(-pi rho r_x r_y).");

  // NDF, LRPB23 Sec. 4.2
  m.def("ndf_eq17", py::vectorize([](double tau0, double beta, double theta_m) {
          return mg::ndf(tau0_in(tau0), beta_in(beta), theta_in("theta_m", theta_m));
        }),
        py::arg("tau0"), py::arg("beta"), py::arg("theta_m"),
        "LRPB23 Eq. 17: D(m) = -ln(1 - tau0) (1 - tau0)^(tan^2/(beta^2 + tan^2)) / tau0 * D_GGX(m; beta),\n"
        "in 1/sr, normalised: integral of D cos theta_m over the hemisphere = 1.");
  m.def("ndf_eq16", py::vectorize([](double tau0, double beta, double theta_m) {
          return mg::ndf_eq16(tau0_in(tau0), beta_in(beta), theta_in("theta_m", theta_m));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta_m"),
        "LRPB23 Eq. 16 (same function as Eq. 17, written with pi rho r_s^2 = -ln(1 - tau0)).");
  m.def("ndf_anisotropic", py::vectorize([](double tau0, double bx, double by, double theta_m, double phi_m) {
          return mg::ndf(grain_field(tau0, bx, by), direction_in("theta_m", theta_m, "phi_m", phi_m));
        }), py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_m"), py::arg("phi_m"),
        "vNDF Eq. 7-8: anisotropic D(m) = det(M) / |M^T m|^4 D1(m'); equals ndf_eq17 when beta_x == beta_y.");
  m.def("ndf_ggx_alpha_tilde", py::vectorize([](double tau0, double beta, double theta_m) {
          return mg::ggx_ndf(mg::equivalent_roughness(tau0_in(tau0), beta_in(beta)), theta_in("theta_m", theta_m));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta_m"),
        "GGX NDF at the equivalent roughness alpha~ of LRPB23 Eq. 18 (suite model ndf_ggx_alpha_tilde).");
  m.def("equivalent_roughness", py::vectorize([](double tau0, double beta) {
          return mg::equivalent_roughness(tau0_in(tau0), beta_in(beta));
        }), py::arg("tau0"), py::arg("beta"),
        "LRPB23 Eq. 18: alpha~ = beta sqrt(-tau0 / ln(1 - tau0)).");
  m.def("ndf_cdf_theta", py::vectorize([](double tau0, double beta, double theta_m) {
          return mg::ndf_cdf_theta(tau0_in(tau0), beta_in(beta), theta_in("theta_m", theta_m));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta_m"),
        "LRPB23 Eq. 19: CDF of theta_m under D(m) cos theta_m.");
  m.def("ggx_ndf", py::vectorize([](double alpha, double theta_m) { return mg::ggx_ndf(argument("alpha", alpha, kPositive), theta_in("theta_m", theta_m)); }),
        py::arg("alpha"), py::arg("theta_m"), "GGX NDF alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2), 1/sr.");

  // Visible filling factor, LRPB23 Sec. 5.1
  m.def("tau_beta_eq21", py::vectorize([](double tau0, double beta, double theta) {
          return mg::tau_beta(tau0_in(tau0), beta_in(beta), theta_in("theta", theta));
        }),
        py::arg("tau0"), py::arg("beta"), py::arg("theta"),
        "LRPB23 Eq. 21: tau_beta = 1 - (1 - tau0)^(gamma_beta(theta) / cos theta), full ellipsoids.");
  m.def("tau_plus_eq22", py::vectorize([](double tau0, double beta, double theta) {
          return mg::tau_plus(tau0_in(tau0), beta_in(beta), theta_in("theta", theta));
        }),
        py::arg("tau0"), py::arg("beta"), py::arg("theta"),
        "LRPB23 Eq. 22 (suite model tau_plus_eq22): visible filling factor of the half-ellipsoids,\n"
        "tau+ = 1 - sqrt((1 - tau_beta)(1 - tau0)); dimensionless, tau+(0) = tau0.");
  m.def("tau_plus_anisotropic", py::vectorize([](double tau0, double bx, double by, double theta, double phi) {
          return mg::tau_plus(grain_field(tau0, bx, by), direction_in("theta", theta, "phi", phi));
        }), py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta"), py::arg("phi"),
        "LRPB23 Eq. 22 in the unit space (any beta_x, beta_y).");
  m.def("layer_weight_eq24", py::vectorize([](double tau0, double beta, double theta_i, double theta_o) {
          const mg::GrainField f = iso(tau0, beta);
          return mg::layer_weight(f, spherical_direction(theta_in("theta_i", theta_i), 0), spherical_direction(theta_in("theta_o", theta_o), 0));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta_i"), py::arg("theta_o"),
        "LRPB23 Eq. 24: w+(i, o) = 1 - sqrt((1 - tau_beta(i))(1 - tau_beta(o))).");

  // Height-correlated masking (vNDF Eq. 3-5, 9-10)
  m.def("tau_height_sigma", py::vectorize([](double tau0, double bx, double by, double theta_i, double phi_i, double h) {
          return mg::filling_factor_at_height(grain_field(tau0, bx, by), direction_in("theta_i", theta_i, "phi_i", phi_i), height_in(h));
        }), py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_i"), py::arg("phi_i"), py::arg("h"),
        "vNDF Eq. 4/10 (suite model tau_height_sigma): tau(i, h) = 1 - exp(-rho' sigma(i', h)),\n"
        "rho' = -ln(1 - tau0)/pi, h the unit-space height in [0, 1]; tau(i, 0) = tau+(i).");
  m.def("g_dist", py::vectorize([](double tau0, double bx, double by, double theta_i, double phi_i, double h) {
          return mg::distant_masking(grain_field(tau0, bx, by), direction_in("theta_i", theta_i, "phi_i", phi_i), height_in(h));
        }), py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_i"), py::arg("phi_i"), py::arg("h"),
        "vNDF Eq. 3/9: height-correlated masking G_dist(i, h) = exp(-rho' sigma_s(i', h)).");
  m.def("projected_cap_area", py::vectorize([](double theta_i, double h) { return mg::projected_cap_area(theta_in("theta_i", theta_i), height_in(h)); }),
        py::arg("theta_i"), py::arg("h"),
        "vNDF Eq. 5: sigma(i, h) = pi (1 - h^2) + sigma_s(i, h), unit-space cap (theta_i unit-space).");

  // Smith Lambda and G1, LRPB23 Sec. 5.2
  m.def("lambda_series", py::vectorize([](double tau0, double beta, double theta, double n) {
          return mg::lambda_series(iso(tau0, beta), theta_in("theta", theta), whole_argument("n", n, 0, 64));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"), py::arg("n") = 4,
        "LRPB23 Eq. 25: Smith Lambda by the series truncated after F_n (closed forms for k <= 4).");
  m.def("lambda_quadrature", py::vectorize([](double tau0, double beta, double theta) {
          return mg::lambda_quadrature(iso(tau0, beta), theta_in("theta", theta));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"),
        "Smith Lambda by quadrature of the exact NDF (Eq. 17); ~1e-10 relative up to 89 deg.");
  m.def("lambda_ggx_alpha_tilde", py::vectorize([](double tau0, double beta, double theta) {
          return mg::lambda_ggx_equivalent(iso(tau0, beta), theta_in("theta", theta));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"), "GGX Lambda at alpha~ (LRPB23 Eq. 18).");
  m.def("g1_smith_quadrature", py::vectorize([](double tau0, double beta, double theta) {
          return 1 / (1 + mg::lambda_quadrature(iso(tau0, beta), theta_in("theta", theta)));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"), "Smith G1 = 1/(1 + Lambda), Lambda by quadrature.");
  m.def("g1_smith_series_n4", py::vectorize([](double tau0, double beta, double theta) {
          return 1 / (1 + mg::lambda_series(iso(tau0, beta), theta_in("theta", theta), 4));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"), "Smith G1 with Lambda from Eq. 25, terms F0..F4.");
  m.def("g1_smith_ggx_alpha_tilde", py::vectorize([](double tau0, double beta, double theta) {
          return 1 / (1 + mg::lambda_ggx_equivalent(iso(tau0, beta), theta_in("theta", theta)));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"), "Smith G1 of GGX at alpha~ (Eq. 18).");
  m.def("g1_exact_tau_plus", py::vectorize([](double tau0, double beta, double theta) {
          const mg::GrainField f = iso(tau0, beta);
          const Vec3 wi = spherical_direction(theta_in("theta", theta), 0);
          return mg::tau_plus(f, wi) / (tau0 * (1 + mg::lambda_quadrature(f, wi)));
        }), py::arg("tau0"), py::arg("beta"), py::arg("theta"),
        "tau+(i) / (tau0 (1 + Lambda_quad(i))): visible grain area over the projected grain area.");

  // Visible NDF (vNDF Eq. 6, 11-13)
  m.def("vndf_eq13", py::vectorize([](double tau0, double bx, double by, double theta_i, double phi_i, double theta_m,
                                      double phi_m) {
          return mg::visible_ndf(grain_field(tau0, bx, by), direction_in("theta_i", theta_i, "phi_i", phi_i), direction_in("theta_m", theta_m, "phi_m", phi_m));
        }), py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_i"), py::arg("phi_i"),
        py::arg("theta_m"), py::arg("phi_m"),
        "vNDF Eq. 6/11-13 (suite model vndf_eq13): D_v(i, m) = tau0 <i.m>+ D(m) G_dist(i, h(m)) /\n"
        "(tau+(i) cos theta_i), per unit solid angle of m; integrates to 1 over m.");

  // BSDFs (LRPB23 Eq. 1-2; vNDF Eq. 1)
  py::class_<mg::MicroSurface>(m, "MicroSurface", "A micro-BRDF of grains or base, one colour channel.")
      .def(py::init([](const std::string& type, double kd, double eta, double kappa, double ior, double alpha) {
             // The ranges of an experiment's [material] keys (sim/micrograin/micrograin_materials.cpp).
             check_argument("kd", kd, {0, 1, false, false});
             check_argument("eta", eta, {0, 100, true, false});
             check_argument("kappa", kappa, {0, 100, false, false});
             check_argument("ior", ior, {1, 4, true, false});
             check_argument("alpha", alpha, {0, 4, true, false});
             mg::MicroSurface s;
             s.type = surface_type(type);
             s.kd = kd;
             s.eta = eta;
             s.kappa = kappa;
             s.ior = ior;
             s.alpha = alpha;
             return s;
           }),
           py::arg("type") = "lambertian", py::arg("kd") = 0.8, py::arg("eta") = 1.5, py::arg("kappa") = 0.0,
           py::arg("ior") = 1.5, py::arg("alpha") = 0.3,
           "type: black, lambertian (kd), conductor (eta, kappa), rough_conductor (eta, kappa, GGX alpha),\n"
           "diffuse_specular (kd body albedo under a smooth interface of index ior).");
  m.def("lrpb23", [](py::object tau0, py::object beta, py::object ti, py::object pi_, py::object to, py::object po,
                     const mg::MicroSurface& grain, const mg::MicroSurface& base, const std::string& lambda,
                     const std::string& part) {
          const mg::LambdaMethod l = lambda_method(lambda);
          if (part != "total" && part != "grain" && part != "base")
            throw ConfigError("<python>", "part", "\"" + part + "\" must be one of total, grain, base");
          auto f = py::vectorize([&](double tau0, double beta, double ti, double pi_, double to, double po) {
            const mg::GrainField f = iso(tau0, beta);
            const Vec3 i = direction_in("theta_i", ti, "phi_i", pi_), o = direction_in("theta_o", to, "phi_o", po);
            double v = 0;
            if (part != "base") v += mg::lrpb23_grain_part(f, grain, i, o, l);
            if (part != "grain") v += mg::lrpb23_base_part(f, base, i, o);
            return v;
          });
          return f(numbers(tau0), numbers(beta), numbers(ti), numbers(pi_), numbers(to), numbers(po));
        }, py::arg("tau0"), py::arg("beta"), py::arg("theta_i"), py::arg("phi_i"), py::arg("theta_o"), py::arg("phi_o"),
        py::arg("grain"), py::arg("base"), py::arg("lambda_method") = "series4", py::arg("part") = "total",
        "LRPB23 Eq. 1-2 without the base's delta lobe (suite models lrpb23_series4 / _quadrature /\n"
        "_ggx with part='total', lrpb23_grain_* with part='grain', lrpb23_base with part='base'):\n"
        "w+ f^S + (1 - w+) f^B, G = 1/(1 + Lambda_i + Lambda_o), Lambda by lambda_method\n"
        "(series4: Eq. 25 n = 4; quadrature; ggx: GGX at alpha~, Eq. 18). 1/sr, no cosine.");
  m.def("gdist_grain", [](py::object tau0, py::object bx, py::object by, py::object ti, py::object pi_, py::object to,
                          py::object po, const mg::MicroSurface& grain) {
          return vectorized([&](double tau0, double bx, double by, double ti, double pi_, double to, double po) {
            return mg::gdist_grain_single_scattering(grain_field(tau0, bx, by), grain, direction_in("theta_i", ti, "phi_i", pi_),
                                                     direction_in("theta_o", to, "phi_o", po));
          }, tau0, bx, by, ti, pi_, to, po);
        }, py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_i"), py::arg("phi_i"),
        py::arg("theta_o"), py::arg("phi_o"), py::arg("grain"),
        "vNDF Eq. 1, grain term tau0 f_S (suite model gdist_grain): single scattering on the grains\n"
        "with G_dist(i, h) G_dist(o, h). 1/sr, no cosine. Add lrpb23(..., part='base') for gdist_total.");
}

}  // namespace mcref::python
