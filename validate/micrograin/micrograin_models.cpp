#include "validate/model_evaluation.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/micrograin/closest_grain.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/height_masking.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/pore_visibility.h"
#include "models/micrograin/smith_lambda.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"
#include "models/micrograin/visible_ndf.h"
#include "models/micrograin/vndf_sampler.h"
#include "sim/micrograin/estimator.h"

namespace mcref {

namespace mg = micrograin;

namespace {

std::vector<ModelInfo> geometry_model_list() {
  std::vector<ModelInfo> models{
      {"p1_eq10", "p1", true, "closest-centre distance density 2 pi rho r exp(-pi rho r^2) (LRPB23 Eq. 8-10)"},
      {"ndf_eq17", "ndf", true, "micrograin NDF (LRPB23 Eq. 16/17)"},
      {"ndf_ggx_alpha_tilde", "ndf", false, "GGX NDF at the equivalent roughness alpha~ (LRPB23 Eq. 18)"},
      {"tau_plus_eq22", "tau_plus", true, "visible filling factor (LRPB23 Eq. 21-22)"},
      {"tau_height_sigma", "tau_height", true,
       "1 - exp(-rho sigma(i, h)), sigma in closed form (LRPB24 via the vNDF paper, Eq. 4/10)"},
      {"g1_exact_tau_plus", "g1", true,
       "tau+(i) / (tau0 (1 + Lambda_quad(i))): visible grain area over the height field's projected grain area"},
      {"g1_g_dist", "g1", true, "projected-area average of the height-correlated G_dist (LRPB24) over the NDF"},
      {"g1_smith_quadrature", "g1", false, "Smith G1 = 1/(1 + Lambda), Lambda by quadrature of the exact NDF"},
      {"g1_smith_series_n4", "g1", false, "Smith G1 with Lambda from the series of LRPB23 Eq. 25, terms F0..F4"},
      {"g1_smith_series_n6", "g1", false,
       "Smith G1 with Lambda from the series of LRPB23 Eq. 25, terms F0..F6 (closed form for any k; issue #15)"},
      {"g1_smith_ggx_alpha_tilde", "g1", false, "Smith G1 of GGX at alpha~ (LRPB23 Eq. 18)"},
      {"g1_conditional_g_dist", "g1_conditional", true, "height-correlated masking G_dist(i, h(m)) (LRPB24)"},
      {"g1_conditional_smith", "g1_conditional", false, "Smith: G1(i) = 1/(1 + Lambda_quad(i)) for every front-facing m"},
      {"pore_visibility_product_eq22", "pore_visibility_independent", true,
       "V(i) V(o), V(d) = (1 - tau+(d)) / (1 - tau0) (LRPB23 Eq. 22)"},
      {"pore_visibility_independence_eq24", "pore_visibility", false,
       "independent visibilities, V(i) V(o): the assumption behind w+ (LRPB23 Eq. 23-24)"},
      {"pore_visibility_union", "pore_visibility", true,
       "exp(-rho (|K_i U K_o| - pi)): one Poisson void probability over the union of the two shadow sets of "
       "Eq. 22, in closed form (issue #15)"},
      {"vndf_eq13", "vndf", true, "visible NDF with height-correlated masking (vNDF paper Eq. 6/11-13)"},
      {"vndf_sampler", "vndf", false,
       "histogram of the vNDF sampler (vNDF paper Sec. 4, Listings 1-4; theta by the tabulated sigma^-1, phi by "
       "the triangle cut of the tent of Eq. 28-31), 2e6 samples per incident direction, binned and folded as the simulation "
       "(approximate: 1024 x 1024 table; its own multinomial noise enters z; Fig. 5's phi histogram is the "
       "phi_conditional case)"},
  };
  for (ModelInfo& m : models) m.kind = "micrograin";
  return models;
}

// ∫∫ h sin theta dtheta dphi over [t0, t1] x [p0, p1], where h vanishes
// beyond the visibility curve <i.m> = 0 (or i = 0: no such curve): nested
// adaptive Gauss-Legendre, the theta integral ending at the curve, the phi
// integral split where the curve crosses theta = t0 or t1, so that both
// integrands are smooth up to kinks that bisection finds (a fixed or 2-D rule
// whose nodes all miss a thin visible sliver would return 0 there). Accurate
// to about rel of the integral's first estimate (issue #15, part 4).
double visible_integral(const std::function<double(double, double)>& h, Vec3 i, double t0, double t1, double p0,
                        double p1, double rel) {
  const double ti = std::acos(std::fmin(1.0, i.z)), phi_i = std::atan2(i.y, i.x);
  // Visible theta < theta_b(phi) when cos(phi - phi_i) < 0: tan theta_b = -1 / (tan theta_i cos(phi - phi_i)).
  auto upper = [&](double phi) {
    const double c = std::sin(ti) * std::cos(phi - phi_i);
    return c < 0 ? std::fmin(t1, std::atan2(i.z, -c)) : t1;
  };
  std::vector<double> cuts{p0};
  for (double t : {t0, t1}) {
    const double c = -1 / (std::tan(ti) * std::tan(t));  // cos(phi - phi_i) where theta_b = t
    if (!(c > -1 && c < 0)) continue;
    for (int k = -2; k <= 2; ++k)
      for (double sign : {-1.0, 1.0}) {
        const double phi = phi_i + sign * std::acos(c) + 2 * kPi * k;
        if (phi > p0 && phi < p1) cuts.push_back(phi);
      }
  }
  cuts.push_back(p1);
  std::sort(cuts.begin(), cuts.end());
  auto inner = [&](double phi, double tol) {
    const double b = upper(phi);
    return b > t0 ? integrate_adaptive([&](double th) { return h(th, phi) * std::sin(th); }, t0, b, tol) : 0.0;
  };
  // First estimate (16-point rules) for the scale, then the adaptive pass.
  static const GaussLegendre g16(16);
  double scale = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    scale += std::fabs(g16.integrate([&](double phi) { return inner(phi, 1e300); }, cuts[k], cuts[k + 1]));
  if (scale == 0) return 0;
  const double tol = rel * scale;
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    sum += integrate_adaptive([&](double phi) { return inner(phi, 0.1 * tol / (p1 - p0)); }, cuts[k], cuts[k + 1],
                              0.5 * tol * (cuts[k + 1] - cuts[k]) / (p1 - p0));
  return sum;
}

// Weighted average of f over a (theta, phi) cell, ∫ f w sin / ∫ w sin, with
// the weight (or f w) vanishing beyond the visibility curve of i (i = +z: none),
// each integral to 1e-8 of itself (far below kCellRelTolerance); NaN if the
// weight vanishes on the cell.
double cell_average(double t0, double t1, double p0, double p1, const std::function<double(double, double)>& f,
                    const std::function<double(double, double)>& w, Vec3 i = {0, 0, 1}) {
  constexpr double kRel = 1e-8;
  const double den = visible_integral(w, i, t0, t1, p0, p1, kRel);
  if (!(den > 0)) return NAN;
  auto fw = [&](double th, double ph) {
    const double x = w(th, ph);
    return x == 0 ? 0 : x * f(th, ph);
  };
  return visible_integral(fw, i, t0, t1, p0, p1, kRel) / den;
}

// The "vndf_sampler" model: per incident direction of the table, kVndfSamplerSamples
// normals from micrograin::VndfSampler::sample (real-space i in, real-space m
// out), histogrammed into the (theta_m, phi_m_rel) cells exactly as
// sim/micrograin/vndf.cpp does (relative azimuth folded into [0, pi] for
// isotropic fields; value = count / (samples * fold * solid angle), a density
// per steradian over all samples). Random streams: run_chunks with key
// stream_seed({kVndfSamplerSeed, direction index}), the direction index
// counting (theta_i, phi_i) row-major as the estimator does, so the histogram
// is fixed and independent of the thread count.
constexpr std::uint64_t kVndfSamplerSamples = 2000000;
constexpr std::uint64_t kVndfSamplerSeed = 0x766e64665f736d70ULL;  // "vndf_smp"

std::vector<double> vndf_sampler_histogram(const Table& t, const MicrograinGeometry& geometry) {
  static const mg::VndfSampler sampler;  // sigma^-1 table, built once (~0.3 s)
  const mg::GrainField f{geometry.tau0, geometry.beta_x, geometry.beta_y};
  const bool folded = !geometry.anisotropic();
  const std::size_t dti = axis_index(t, "theta_i"), dpi = axis_index(t, "phi_i");
  const std::size_t dth = axis_index(t, "theta_m"), dph = axis_index(t, "phi_m_rel");
  const Axis& ti = t.axes[dti];
  const Axis& pi = t.axes[dpi];
  const Axis& th = t.axes[dth];
  const Axis& ph = t.axes[dph];
  const std::size_t cells = th.size() * ph.size();
  const double fold = folded ? 2.0 : 1.0;
  std::vector<double> out(t.cells(), NAN);
  std::uint64_t dir = 0;
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < pi.size(); ++b, ++dir) {
      const double phi_i = pi.values[b];
      const Vec3 wi = spherical_direction(ti.values[a], phi_i);
      const Sums acc = run_chunks(kVndfSamplerSamples, cells, stream_seed({kVndfSamplerSeed, dir}),
                                  [&](Rng& rng, std::uint64_t n, Sums& s) {
                                    for (std::uint64_t k = 0; k < n; ++k) {
                                      const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                                      const Vec3 m = sampler.sample(f, wi, u1, u2, u3);
                                      const int c = th.find_bin(spherical_theta(m));
                                      const int d = ph.find_bin(relative_azimuth(spherical_phi(m), phi_i, folded));
                                      if (c >= 0 && d >= 0) s[c * ph.size() + d] += 1;
                                    }
                                  });
      std::vector<std::size_t> idx(t.axes.size(), 0);
      idx[dti] = a;
      idx[dpi] = b;
      for (std::size_t c = 0; c < th.size(); ++c)
        for (std::size_t d = 0; d < ph.size(); ++d) {
          idx[dth] = c;
          idx[dph] = d;
          const double w = fold * cell_solid_angle(th.lower(c), th.upper(c), ph.lower(d), ph.upper(d));
          out[t.index(idx)] = acc[c * ph.size() + d] / (static_cast<double>(kVndfSamplerSamples) * w);
        }
    }
  return out;
}

double phi_i_of(const Table& t, const std::vector<std::size_t>& idx) {
  for (std::size_t d = 0; d < t.axes.size(); ++d)
    if (t.axes[d].name == "phi_i") return t.axes[d].values[idx[d]];
  const auto it = t.attributes.find("phi_i");
  return it == t.attributes.end() ? 0.0 : std::stod(it->second);
}

std::vector<double> evaluate_geometry_model(const std::string& model, const Table& t, const Experiment& ex) {
  const MicrograinGeometry& geometry = ex.micrograin;
  const mg::GrainField f{geometry.tau0, geometry.beta_x, geometry.beta_y};
  const bool isotropic = !geometry.anisotropic();
  const double beta = geometry.beta_x;
  std::vector<double> out(t.cells(), NAN);
  const double rho = mg::unit_density(geometry.tau0);
  auto normal = [](double th, double ph) { return spherical_direction(th, ph); };

  if (t.quantity == "p1") {
    const Axis& r = t.axes[0];
    for (std::size_t b = 0; b < r.size(); ++b)
      out[b] = (mg::closest_grain_distance_cdf(r.upper(b), rho) - mg::closest_grain_distance_cdf(r.lower(b), rho)) /
               (r.upper(b) - r.lower(b));
    return out;
  }
  if (t.quantity == "ndf") {
    const Axis& th = t.axes[0];
    const Axis& ph = t.axes[1];
    const double alpha = isotropic ? mg::equivalent_roughness(geometry.tau0, beta) : 0;
    for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
      auto d = [&](double a, double b) {
        return model == "ndf_eq17" ? mg::ndf(f, normal(a, b)) : mg::ggx_ndf(alpha, a);
      };
      out[k] = cell_average(th.lower(i[0]), th.upper(i[0]), ph.lower(i[1]), ph.upper(i[1]), d,
                            [](double a, double) { return std::cos(a); });
    });
    return out;
  }
  if (t.quantity == "tau_plus" || t.quantity == "g1") {
    for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
      const double theta = t.axes[0].values[i[0]], phi = t.axes[1].values[i[1]];
      const Vec3 wi = spherical_direction(theta, phi);
      if (model == "tau_plus_eq22") out[k] = mg::tau_plus(f, wi);
      else if (model == "g1_exact_tau_plus") out[k] = mg::tau_plus(f, wi) / (geometry.tau0 * (1 + mg::lambda_quadrature(f, wi)));
      else if (model == "g1_smith_quadrature") out[k] = 1 / (1 + mg::lambda_quadrature(f, wi));
      else if (model == "g1_smith_series_n4") out[k] = 1 / (1 + mg::lambda_series(f, theta, 4));
      else if (model == "g1_smith_series_n6") out[k] = 1 / (1 + mg::lambda_series(f, theta, 6));
      else if (model == "g1_smith_ggx_alpha_tilde") out[k] = 1 / (1 + mg::lambda_ggx_equivalent(f, theta));
      else if (model == "g1_g_dist") {
        // Average of G_dist over the height field's normals, weighted by projected area <i.m>+ D(m).
        out[k] = cell_average(
            0, kPi / 2, phi, phi + 2 * kPi,
            [&](double x, double y) { return mg::distant_masking(f, wi, mg::unit_height(f, normal(x, y))); },
            [&](double x, double y) {
              const Vec3 m = normal(x, y);
              return std::fmax(0.0, dot(wi, m)) * mg::ndf(f, m);
            },
            wi);
      }
    });
    return out;
  }
  if (t.quantity == "tau_height") {
    for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
      const Vec3 wi = spherical_direction(t.axes[0].values[i[0]], t.axes[1].values[i[1]]);
      out[k] = mg::filling_factor_at_height(f, wi, t.axes[2].values[i[2]]);
    });
    return out;
  }
  if (t.quantity == "pore_visibility" || t.quantity == "pore_visibility_independent") {
    for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
      const double phi_i = phi_i_of(t, i);
      const Vec3 wi = spherical_direction(t.axes[0].values[i[0]], phi_i);
      const Vec3 wo = spherical_direction(t.axes[1].values[i[1]], phi_i + t.axes[2].values[i[2]]);
      out[k] = model == "pore_visibility_union" ? mg::pore_visibility_union(f, wi, wo) : mg::pore_visibility_product(f, wi, wo);
    });
    return out;
  }
  if (model == "vndf_sampler") {
    if (t.quantity != "vndf") throw std::invalid_argument("model vndf_sampler predicts vndf tables only");
    return vndf_sampler_histogram(t, geometry);
  }
  if (t.quantity == "vndf" || t.quantity == "g1_conditional") {
    const std::size_t dth = axis_index(t, "theta_m"), dph = axis_index(t, "phi_m_rel");
    for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
      const double phi_i = t.axes[1].values[i[1]];
      const Vec3 wi = spherical_direction(t.axes[0].values[i[0]], phi_i);
      const Axis& th = t.axes[dth];
      const Axis& ph = t.axes[dph];
      const double t0 = th.lower(i[dth]), t1 = th.upper(i[dth]);
      const double p0 = phi_i + ph.lower(i[dph]), p1 = phi_i + ph.upper(i[dph]);
      if (t.quantity == "vndf") {
        // The weight 1 on the whole cell; f (the vNDF) vanishes beyond the visibility curve.
        const double area = (std::cos(t0) - std::cos(t1)) * (p1 - p0);
        out[k] = visible_integral([&](double a, double b) { return mg::visible_ndf(f, wi, normal(a, b)); }, wi, t0, t1,
                                  p0, p1, 1e-8) /
                 area;
      } else {
        auto w = [&](double a, double b) {
          const Vec3 m = normal(a, b);
          return std::fmax(0.0, dot(wi, m)) * mg::ndf(f, m);
        };
        const double smith = 1 / (1 + mg::lambda_quadrature(f, wi));
        out[k] = cell_average(t0, t1, p0, p1,
                              [&](double a, double b) {
                                return model == "g1_conditional_g_dist"
                                           ? mg::distant_masking(f, wi, mg::unit_height(f, normal(a, b)))
                                           : smith;
                              },
                              w, wi);
      }
    });
    return out;
  }
  throw std::invalid_argument("no model evaluation for quantity " + t.quantity);
}

// The vndf_sampler histogram's own noise: a cell of value v holds
// k = v N w of the N samples (w its folded solid angle), multinomial:
// se = sqrt(k (1 - k/N)) / (N w).
std::vector<double> evaluate_geometry_stderr(const std::string& model, const Table& t, const Experiment& ex,
                                             const std::vector<double>& values) {
  if (model != "vndf_sampler") return {};
  const double n = static_cast<double>(kVndfSamplerSamples), fold = ex.micrograin.anisotropic() ? 1.0 : 2.0;
  const std::size_t dth = axis_index(t, "theta_m"), dph = axis_index(t, "phi_m_rel");
  const Axis& th = t.axes[dth];
  const Axis& ph = t.axes[dph];
  std::vector<double> se(t.cells(), NAN);
  for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
    const double w = fold * cell_solid_angle(th.lower(i[dth]), th.upper(i[dth]), ph.lower(i[dph]), ph.upper(i[dph]));
    const double count = values[k] * n * w;
    se[k] = std::sqrt(std::fmax(0.0, count * (1 - count / n))) / (n * w);
  });
  return se;
}

std::string geometry_model_unsupported(const std::string& model, const Experiment& ex) {
  if (ex.micrograin.anisotropic() && (model == "ndf_ggx_alpha_tilde" || model == "g1_smith_series_n4" ||
                                      model == "g1_smith_series_n6" || model == "g1_smith_ggx_alpha_tilde"))
    return "model " + model + " is defined for isotropic grains only (beta_x = beta_y)";
  return "";
}

}  // namespace

const ModelFamily& micrograin_geometry_models() {
  static const ModelFamily family{geometry_model_list(), evaluate_geometry_model, evaluate_geometry_stderr,
                                  geometry_model_unsupported};
  return family;
}

}  // namespace mcref
