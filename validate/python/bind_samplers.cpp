// mcref.samplers: every sampler as (samples, pdf), from given uniforms
// (array of shape (n, k), values in [0, 1)) or from a seed (n draws of the
// project's Rng, models/core/rng.h), for users' own chi-square tests.
#include <cmath>
#include <functional>

#include "models/core/rng.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/phase_sampling.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/ndf_sampling.h"
#include "models/micrograin/visible_ndf.h"
#include "models/micrograin/vndf_sampler.h"
#include "models/sggx/flake_phase.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/table_plan.h"
#include "validate/python/bindings.h"

namespace mcref::python {

namespace {

using Uniforms = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The (n, k) uniforms: given, or drawn from Rng(seed).
std::vector<double> uniforms(const py::object& u, const py::object& seed, std::int64_t n, int k) {
  if (!u.is_none()) {
    if (!seed.is_none() || n != 0) throw ConfigError("<python>", "u", "give either uniforms u or a seed (with n), not both");
    const Uniforms a = Uniforms::ensure(u);
    if (!a || a.ndim() != 2 || a.shape(1) != k)
      throw ConfigError("<python>", "u", "must be an array of shape (n, " + std::to_string(k) + ")");
    std::vector<double> v(a.data(), a.data() + a.size());
    for (double x : v)
      if (!(x >= 0 && x < 1)) throw ConfigError("<python>", "u", "uniforms must be in [0, 1)");
    return v;
  }
  if (seed.is_none()) throw ConfigError("<python>", "u", "give either uniforms u or a seed (with n)");
  if (n < 1) throw ConfigError("<python>", "n", "must be at least 1");
  // The uniforms and the samples (up to 4 numbers each), against the memory budget
  // (before: n * k wrapped round to 0 for n = 2^62 and gave empty arrays).
  std::string why;
  const double budget = memory_budget(&why), need = 8.0 * static_cast<double>(n) * (k + 4);
  if (need > budget)
    throw ConfigError("<python>", "n", "= " + std::to_string(n) + " samples would need about " + bytes_text(need) +
                                           ", more than the budget of " + bytes_text(budget) + " (" + why + ")");
  Rng rng(integer_argument("seed", seed, UINT64_MAX));
  std::vector<double> v(static_cast<std::size_t>(n) * k);
  for (double& x : v) x = rng.uniform();
  return v;
}

// Runs `draw` on each row of uniforms: fills the unit vector and returns the pdf.
py::tuple run(const std::vector<double>& u, int k, const std::function<double(const double*, Vec3&)>& draw) {
  const py::ssize_t n = static_cast<py::ssize_t>(u.size() / k);
  py::array_t<double> samples({n, py::ssize_t{3}}), pdf(n);
  double* s = samples.mutable_data();
  double* p = pdf.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t r = 0; r < n; ++r) {
      Vec3 d;
      p[r] = draw(&u[r * k], d);
      s[3 * r] = d.x;
      s[3 * r + 1] = d.y;
      s[3 * r + 2] = d.z;
    }
  }
  return py::make_tuple(samples, pdf);
}


const micrograin::VndfSampler& vndf_sampler() {
  static const micrograin::VndfSampler sampler;  // its table is built once (~0.3 s)
  return sampler;
}

#define MCREF_SAMPLE_ARGS py::arg("u") = py::none(), py::arg("seed") = py::none(), py::arg("n") = 0

}  // namespace

void bind_samplers(py::module_& root) {
  py::module_ m = root.def_submodule(
      "samplers",
      "Samplers returning (samples, pdf): samples an (n, 3) array of unit vectors (z the macro\n"
      "normal), pdf per unit solid angle. Uniforms: u of shape (n, k) in [0, 1), or seed and n.");

  m.def("micrograin_ndf", [](double tau0, double bx, double by, py::object u, py::object seed, std::int64_t n) {
          const micrograin::GrainField f = grain_field(tau0, bx, by);
          return run(uniforms(u, seed, n, 2), 2, [&](const double* x, Vec3& m) {
            m = micrograin::sample_ndf(f, x[0], x[1]);
            return micrograin::ndf_pdf(f, m);
          });
        }, py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), MCREF_SAMPLE_ARGS,
        "Normals m with density D(m) cos theta_m (LRPB23 Eq. 19-20, sign-corrected; vNDF Eq. 14); k = 2.");
  m.def("micrograin_vndf", [](double tau0, double bx, double by, double theta_i, double phi_i, py::object u,
                              py::object seed, std::int64_t n) {
          const micrograin::GrainField f = grain_field(tau0, bx, by);
          check_argument("theta_i", theta_i, {0, kPi / 2, false, false});
          check_argument("phi_i", phi_i, {-INFINITY, INFINITY, true, true});
          const Vec3 wi = spherical_direction(theta_i, phi_i);
          const micrograin::VndfSampler& s = vndf_sampler();
          return run(uniforms(u, seed, n, 3), 3, [&](const double* x, Vec3& m) {
            m = s.sample(f, wi, x[0], x[1], x[2]);
            return micrograin::visible_ndf(f, wi, m);
          });
        }, py::arg("tau0"), py::arg("beta_x"), py::arg("beta_y"), py::arg("theta_i"), py::arg("phi_i"), MCREF_SAMPLE_ARGS,
        "Visible normals of direction i (vNDF Sec. 4, Listings 1-4); pdf = D_v(i, m) (Eq. 6); k = 3.\n"
        "theta' is inverted through a 16-bit table, so the samples follow D_v to ~1e-4, not exactly.");
  m.def("sggx_visible_normal", [](const sggx::Sggx& sg, double theta, double phi, py::object u, py::object seed,
                                  std::int64_t n) {
          const Vec3 w = spherical_direction(theta, phi);
          return run(uniforms(u, seed, n, 2), 2, [&](const double* x, Vec3& m) {
            m = sggx::sample_visible_normal(sg, w, x[0], x[1]);
            return sggx::visible_ndf(sg, w, m);
          });
        }, py::arg("sggx"), py::arg("theta"), py::arg("phi"), MCREF_SAMPLE_ARGS,
        "SGGX visible normals of w (Heitz 2015 Sec. 5, via Cholesky); pdf <w.m>+ D(m) / sigma(w); k = 2.");
  m.def("sggx_phase", [](const sggx::Sggx& sg, double theta_i, double phi_i, py::object u, py::object seed,
                         std::int64_t n) {
          const Vec3 wi = spherical_direction(theta_i, phi_i);
          return run(uniforms(u, seed, n, 2), 2, [&](const double* x, Vec3& wo) {
            const sggx::PhaseSample s = sggx::sample_specular_flake_phase(sg, 1.0, 1.0, wi, x[0], x[1]);
            wo = s.wo;
            return s.valid ? s.pdf : 0.0;
          });
        }, py::arg("sggx"), py::arg("theta_i"), py::arg("phi_i"), MCREF_SAMPLE_ARGS,
        "Specular SGGX flake phase: wo ~ f_p(wi -> .) = D(h) / (4 sigma(wi)) (SpongeCake Eq. 4), wi toward\n"
        "the light; pdf = f_p; k = 2.");
  m.def("lambert_sphere_phase", [](std::array<double, 3> propagation, py::object u, py::object seed, std::int64_t n) {
          const Vec3 p{propagation[0], propagation[1], propagation[2]};
          if (!(std::isfinite(dot(p, p)) && dot(p, p) > 0))
            throw ConfigError("<python>", "propagation", "must be a finite, non-zero vector");
          const Vec3 d = normalize(p);
          return run(uniforms(u, seed, n, 4), 4, [&](const double* x, Vec3& wo) {
            const double mu = lambert_sphere::sample_phase_cosine_exact(x[0], x[1], x[2]);
            wo = lambert_sphere::scattered_direction(d, mu, x[3]);
            return lambert_sphere::phase_function(dot(d, wo));
          });
        }, py::arg("propagation") = std::array<double, 3>{0, 0, -1}, MCREF_SAMPLE_ARGS,
        "Lambert-sphere phase (d'Eon 2021 Eq. 5, exact, three uniforms, then a uniform azimuth about the\n"
        "propagation direction); pdf p(mu) of Eq. 1 per steradian, mu = propagation.wo; k = 4.");
}

}  // namespace mcref::python
