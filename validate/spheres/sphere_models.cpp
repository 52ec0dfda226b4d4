// Models of Lambertian-sphere volumes (d'Eon 2021) on the cells of the sphere
// tables: brdf cells are cosine-weighted bin averages over theta_o x phi
// (Gauss-Legendre 8 x 8 per cell), per RGB channel (albedo of that channel);
// phase cells are bin averages over mu; albedo cells integrate the BRDF over
// the outgoing hemisphere (total component only, other cells NaN).
//
// Which model is exact for which simulation:
//   phase_eq1                 exact for the single-sphere phase measure;
//   single_scattering_eq10    exact for order 1 of the volumetric half-space
//                             (placement = "volumetric"; refused for packings,
//                             which only tend to it: single_scattering_eq10_dilute);
//   everything else           approximate: d'Eon's multiple scattering uses the
//                             three-term truncation of Eq. 1 (Eq. 7-8), so even
//                             ReferenceBrdf (exact three-term solution) is not the
//                             exact answer for the exact phase function.
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "models/lambert_sphere/albedo_mapping.h"
#include "models/lambert_sphere/brdf.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/fast_brdf.h"
#include "models/lambert_sphere/phase_sampling.h"
#include "models/lambert_sphere/reference_brdf.h"
#include "models/lambert_sphere/single_scattering.h"
#include "models/core/quadrature.h"
#include "sim/experiment/simulate.h"
#include "validate/model_evaluation.h"

namespace mcref {

namespace ls = lambert_sphere;

namespace {

// Paths of the volumetric_mc reference per path of the packing it checks.
constexpr int kReferencePathFactor = 8;

// f(c, mu_i, mu_o, phi) in 1/sr without the cosine.
using BrdfFn = std::function<double(double, double, double, double)>;

ls::BrdfOptions exact_ingredients(ls::FirstModeVariant v) {
  ls::BrdfOptions o;
  o.first_mode = v;
  o.h1 = ls::H1Source::exact;
  o.exact_h0 = true;
  o.exact_constants = true;
  return o;
}

// Models built once per (variant, albedo): tabulated H-functions, exact constants.
template <class M>
const M& cached(int variant, double c, const std::function<std::unique_ptr<M>(double)>& make) {
  static std::mutex mutex;
  static std::map<std::pair<int, double>, std::unique_ptr<M>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find({variant, c});
  if (it == cache.end()) it = cache.emplace(std::make_pair(variant, c), make(c)).first;
  return *it->second;
}

// variant: 0 published, 1 corrected (log-separable H1), 2 corrected (H1 as
// printed), 3 published with exact ingredients, 4 corrected with exact ingredients.
std::unique_ptr<ls::Brdf> make_deon(int variant, double c) {
  ls::BrdfOptions o;
  if (variant == 1 || variant == 2) o.first_mode = ls::FirstModeVariant::corrected;
  if (variant == 1) o.h1 = ls::H1Source::log_separable_fit;
  if (variant == 3) o = exact_ingredients(ls::FirstModeVariant::published);
  if (variant == 4) o = exact_ingredients(ls::FirstModeVariant::corrected);
  // Exact constants need c < 1.
  return std::make_unique<ls::Brdf>(variant >= 3 ? std::min(c, 0.9999) : c, o);
}

const ls::Brdf& deon(double c, int variant) {
  return cached<ls::Brdf>(variant, c, [variant](double x) { return make_deon(variant, x); });
}

const ls::ReferenceBrdf& reference(double c) {
  return cached<ls::ReferenceBrdf>(-1, std::min(c, 0.9999), [](double c) { return std::make_unique<ls::ReferenceBrdf>(c, true); });
}

BrdfFn brdf_model(const std::string& name) {
  if (name == "single_scattering_eq10" || name == "single_scattering_eq10_dilute")
    return [](double c, double mi, double mo, double phi) { return ls::single_scattering(c, mi, mo, phi); };
  if (name == "deon_fast_eq41") return [](double c, double mi, double mo, double phi) { return ls::brdf_fast(c, mi, mo, phi); };
  if (name == "reference_three_term")
    return [](double c, double mi, double mo, double phi) { return reference(c)(mi, mo, phi); };
  static const std::map<std::string, int> variants{{"deon_published", 0},
                                                    {"deon_corrected", 1},
                                                    {"deon_corrected_h1_printed", 2},
                                                    {"deon_published_exact_h", 3},
                                                    {"deon_corrected_exact_h", 4}};
  const auto it = variants.find(name);
  if (it == variants.end()) throw std::invalid_argument("no sphere model " + name);
  const int v = it->second;
  return [v](double c, double mi, double mo, double phi) { return deon(c, v)(mi, mo, phi); };
}

std::vector<ModelInfo> model_list() {
  std::vector<ModelInfo> m{
      {"phase_eq1", "phase", true, "Lambert-sphere phase function, density of mu: 2 pi p(mu) (d'Eon Eq. 1)"},
      {"single_scattering_eq10", "brdf", true,
       "single scattering c p(-wi.wo)/(mu_i + mu_o) (Eq. 10), exact for the volumetric half-space", "spheres",
       "order1_sphere"},
      {"single_scattering_eq10_dilute", "brdf", false,
       "Eq. 10 against the first order of an explicit packing (exact only in the dilute limit)", "spheres",
       "order1_sphere"},
      {"deon_published", "brdf", false, "Eq. 11-12 as published: Eq. 28 (Eq. 22 - 384 pi term), fits Eq. 23-27, 31-37",
       "spheres", "total"},
      {"deon_corrected", "brdf", false,
       "Eq. 11-12 with the corrected cos(phi) mode 2 x Eq. 22 - 192 pi term, log-separable H1 fit, other fits published",
       "spheres", "total"},
      {"deon_corrected_h1_printed", "brdf", false,
       "Eq. 11-12 with the corrected cos(phi) mode and H1 by Eq. 23-25 as printed", "spheres", "total"},
      {"deon_published_exact_h", "brdf", false,
       "Eq. 11-12 with the published cos(phi) mode (Eq. 28) but exact H0, H1 and exact l, m, A-F", "spheres", "total"},
      {"deon_corrected_exact_h", "brdf", false,
       "Eq. 11-12 with the corrected cos(phi) mode and exact H0, H1, l, m, A-F (f_m^(2) = 0)", "spheres", "total"},
      {"deon_fast_eq41", "brdf", false, "fast BRDF, Eq. 41 (with Eq. 10 and Eq. 40)", "spheres", "total"},
      {"reference_three_term", "brdf", false,
       "exact Eq. 10 + exact three-term half-space multiple scattering, modes m = 0, 1, 2 (no fits)", "spheres",
       "total"},
      {"volumetric_mc", "brdf", false,
       "the volumetric half-space (placement = \"volumetric\", same albedo, measure and depth rule) simulated with " +
           std::to_string(kReferencePathFactor) + "x the paths: the dilute limit an explicit packing tends to",
       "spheres", ""},
      {"albedo_reference_three_term", "albedo", false,
       "directional albedo of reference_three_term (hemispherical quadrature), total component", "spheres"},
      {"albedo_deon_corrected", "albedo", false, "directional albedo of deon_corrected, total component", "spheres"},
      {"phase_three_term", "phase", false,
       "three-term truncation of Eq. 1 (Eq. 7-8: 1 - 4 mu / 3 + 5 P2(mu) / 16), as d'Eon's multiple scattering uses it",
       "spheres"},
      // Fourier modes f^(k), k = 0, 1, 2 (table <brdf>_modes, Eq. 9 convention).
      {"modes_deon_published", "brdf_modes", false,
       "modes of deon_published: exact-phase single-scattering modes of Eq. 10 + Eq. 38 (k = 0) + Eq. 28 (k = 1), "
       "fits; k = 2 single scattering only (f_m^(2) = 0)",
       "spheres"},
      {"modes_deon_corrected", "brdf_modes", false,
       "modes of deon_corrected: as modes_deon_published with 2 x Eq. 22 - 192 pi term (log-separable H1)", "spheres"},
      {"modes_eq30_eq22", "brdf_modes", false,
       "f^(0) = Eq. 30 and f^(1) = Eq. 22 as published (fits; all orders, three-term phase function); k = 2 not modelled",
       "spheres"},
      {"modes_eq30_2x_eq22", "brdf_modes", false,
       "f^(0) = Eq. 30 and f^(1) = 2 x Eq. 22 (the corrected cos(phi) mode; fits, log-separable H1); k = 2 not modelled", "spheres"},
      {"modes_three_term_exact", "brdf_modes", false,
       "exact modes k = 0, 1, 2 of the three-term half-space, all orders (ReferenceBrdf::mode, no fits): what Eq. 30 "
       "and 2 x Eq. 22 approximate",
       "spheres"},
      {"modes_reference_three_term", "brdf_modes", false,
       "modes of reference_three_term: exact-phase single-scattering modes + exact three-term multiple-scattering modes",
       "spheres"},
      {"f0_eq30", "brdf_modes", false, "f^(0) of Eq. 30 (fits) on the k = 0 cells only: its error is d'Eon's Fig. 5",
       "spheres"},
      {"f0_deon_published", "brdf_modes", false,
       "f^(0) of deon_published (exact-phase single scattering + Eq. 38) on the k = 0 cells only", "spheres"},
      {"f0_reference_three_term", "brdf_modes", false,
       "f^(0) of reference_three_term on the k = 0 cells only (the three-term truncation error alone)", "spheres"},
      // Spherical albedo (table <brdf>_kd).
      {"kd_eq40", "spherical_albedo", false, "k_d from c by Eq. 40 (fit)", "spheres"},
      {"kd_eq30", "spherical_albedo", false, "k_d = 4 pi \\int\\int f^(0) mu_i mu_o of Eq. 30 (fits)", "spheres"},
      {"kd_reference_three_term", "spherical_albedo", false,
       "k_d of reference_three_term (exact single scattering + exact three-term multiple scattering)", "spheres"},
  };
  for (ModelInfo& x : m) x.kind = "spheres";
  return m;
}

// The volumetric counterpart of the experiment's packing, simulated through
// the public entry point (cached per configuration and table).
const Table& volumetric_table(const Table& t, const Experiment& ex) {
  static std::mutex mutex;
  static std::map<std::string, std::vector<Table>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  const Measure* measure = nullptr;
  for (const Measure& m : ex.measures)
    if (m.quantity == "brdf" && (t.name == m.name || t.name.rfind(m.name + "_", 0) == 0)) measure = &m;
  if (!measure) throw std::invalid_argument("volumetric_mc: no brdf measure makes table " + t.name);
  const std::string key = ex.text + "\n#" + measure->name;
  auto it = cache.find(key);
  if (it == cache.end()) {
    Experiment v = ex;
    v.spheres.placement = SpherePlacement::volumetric;
    v.measures = {*measure};
    v.measures[0].samples *= kReferencePathFactor;
    v.run.seed = mix64(ex.run.seed ^ 0x766f6c756d65ull);  // independent of the packing's streams
    SimulateOptions o;
    o.quiet = true;
    o.label = "volumetric_mc";
    it = cache.emplace(key, simulate(v, o)).first;
  }
  for (const Table& r : it->second)
    if (r.name == t.name) return r;
  throw std::invalid_argument("volumetric_mc: the volumetric run has no table " + t.name);
}

std::vector<double> phase_values(const Table& t) {
  const Axis& mu = t.axes[axis_index(t, "mu")];
  std::vector<double> v(t.cells());
  // Bin average of 2 pi p(mu) = (F(b) - F(a)) / (b - a), with 1 - F from the
  // forward-accurate complement.
  for (std::size_t i = 0; i < mu.size(); ++i)
    v[i] = (ls::phase_ccdf_mu(mu.lower(i)) - ls::phase_ccdf_mu(mu.upper(i))) / (mu.upper(i) - mu.lower(i));
  return v;
}

std::vector<double> brdf_values(const BrdfFn& f, const Table& t, const Experiment& ex) {
  const int ai = axis_index(t, "theta_i"), ao = axis_index(t, "theta_o"), ap = axis_index(t, "phi"), ac = axis_index(t, "channel");
  static const GaussLegendre gl(8);
  std::vector<double> v(t.cells());
  std::map<std::vector<std::size_t>, double> memo;  // (theta_i, theta_o, phi, channel) -> value
  for_each_cell(t, [&](std::size_t flat, const std::vector<std::size_t>& idx) {
    const std::vector<std::size_t> key{idx[ai], idx[ao], idx[ap], idx[ac]};
    const auto it = memo.find(key);
    if (it != memo.end()) {
      v[flat] = it->second;
      return;
    }
    const double c = ex.spheres.albedo[static_cast<int>(t.axes[ac].values[idx[ac]])];
    const double mu_i = std::cos(t.axes[ai].values[idx[ai]]);
    const Axis& o = t.axes[ao];
    const double mu_hi = std::cos(o.lower(idx[ao])), mu_lo = std::cos(o.upper(idx[ao]));
    const double p0 = t.axes[ap].lower(idx[ap]), p1 = t.axes[ap].upper(idx[ap]);
    double num = 0, den = 0;
    for (std::size_t a = 0; a < gl.x.size(); ++a) {
      const double mu = 0.5 * (mu_lo + mu_hi) + 0.5 * (mu_hi - mu_lo) * gl.x[a];
      for (std::size_t b = 0; b < gl.x.size(); ++b) {
        const double phi = 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * gl.x[b];
        const double w = gl.w[a] * gl.w[b] * mu;
        num += w * f(c, mu_i, mu, phi);
        den += w;
      }
    }
    v[flat] = memo[key] = num / den;
  });
  return v;
}

// Directional albedo: \int f mu_o d omega_o, 24 x 24 Gauss-Legendre in
// (mu_o, phi in [0, pi]) times 2, on the total-component cells.
std::vector<double> albedo_values(const BrdfFn& f, const Table& t, const Experiment& ex) {
  const int ai = axis_index(t, "theta_i"), acomp = axis_index(t, "component"), ac = axis_index(t, "channel");
  static const GaussLegendre gl(24);
  const std::size_t total = t.axes[acomp].size() - 1;
  std::vector<double> v(t.cells(), NAN);
  std::map<std::pair<std::size_t, std::size_t>, double> memo;
  for_each_cell(t, [&](std::size_t flat, const std::vector<std::size_t>& idx) {
    if (idx[acomp] != total) return;
    const auto key = std::make_pair(idx[ai], idx[ac]);
    if (!memo.count(key)) {
      const double c = ex.spheres.albedo[static_cast<int>(t.axes[ac].values[idx[ac]])];
      const double mu_i = std::cos(t.axes[ai].values[idx[ai]]);
      double s = 0;
      for (std::size_t a = 0; a < gl.x.size(); ++a) {
        const double mu = 0.5 + 0.5 * gl.x[a];
        for (std::size_t b = 0; b < gl.x.size(); ++b) {
          const double phi = 0.5 * kPi * (1 + gl.x[b]);
          s += 0.5 * gl.w[a] * 0.5 * kPi * gl.w[b] * mu * f(c, mu_i, mu, phi);
        }
      }
      memo[key] = 2 * s;
    }
    v[flat] = memo[key];
  });
  return v;
}

// Bin average of 2 pi p_3(mu) = (1 - 4 mu / 3 + 5 P2(mu) / 16) / 2, in closed form.
std::vector<double> phase_three_term_values(const Table& t) {
  const Axis& mu = t.axes[axis_index(t, "mu")];
  const auto F = [](double x) { return 0.5 * (x - 2 * x * x / 3 + 5.0 / 32 * (x * x * x - x)); };
  std::vector<double> v(t.cells());
  for (std::size_t i = 0; i < mu.size(); ++i) v[i] = (F(mu.upper(i)) - F(mu.lower(i))) / (mu.upper(i) - mu.lower(i));
  return v;
}

// Mode k of the single scattering Eq. 10 with the exact phase function, memoized.
double ss_mode_exact(double c, double mi, double mo, int k) {
  static std::mutex mutex;
  static std::map<std::tuple<double, double, double, int>, double> memo;
  const auto key = std::make_tuple(c, mi, mo, k);
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = memo.find(key);
    if (it != memo.end()) return it->second;
  }
  const double v = ls::single_scattering_mode_numeric(c, mi, mo, k, ls::PhaseModel::exact);
  std::lock_guard<std::mutex> lock(mutex);
  return memo[key] = v;
}

// Mode k (0, 1, 2) of a model at (c, mu_i, mu_o); NaN where it does not model k.
using ModeFn = std::function<double(double, double, double, int)>;

ModeFn mode_model(const std::string& name) {
  const double nan = NAN;
  if (name == "modes_deon_published" || name == "modes_deon_corrected" || name == "f0_deon_published") {
    const int v = name == "modes_deon_corrected" ? 1 : 0;
    const bool only0 = name[0] == 'f';
    return [v, only0, nan](double c, double mi, double mo, int k) {
      if (only0 && k != 0) return nan;
      const ls::Brdf& b = deon(c, v);
      const double m = k == 0 ? b.multiple_zeroth_mode(mi, mo) : (k == 1 ? b.multiple_first_mode(mi, mo) : 0.0);
      return ss_mode_exact(c, mi, mo, k) + m;
    };
  }
  if (name == "modes_eq30_eq22" || name == "modes_eq30_2x_eq22" || name == "f0_eq30") {
    const double scale = name == "modes_eq30_2x_eq22" ? 2 : 1;
    const bool only0 = name[0] == 'f';
    return [scale, only0, nan](double c, double mi, double mo, int k) {
      // The corrected mode with the log-separable H1 (deon_corrected's); Eq. 23-25 as printed otherwise.
      const ls::Brdf& b = deon(c, scale == 2 ? 1 : 0);
      if (k == 0) return b.zeroth_mode(mi, mo);
      if (k == 1 && !only0) return scale * b.first_mode_eq22(mi, mo);
      return nan;
    };
  }
  if (name == "modes_three_term_exact")
    return [](double c, double mi, double mo, int k) { return reference(c).mode(k, mi, mo); };
  if (name == "modes_reference_three_term" || name == "f0_reference_three_term") {
    const bool only0 = name[0] == 'f';
    return [only0, nan](double c, double mi, double mo, int k) {
      if (only0 && k != 0) return nan;
      return ss_mode_exact(c, mi, mo, k) + reference(c).multiple_mode(k, mi, mo);
    };
  }
  throw std::invalid_argument("no sphere mode model " + name);
}

// Mode cells: point theta_i, cosine-weighted bin average over theta_o (8-point
// Gauss-Legendre in mu_o), as the table estimates them.
std::vector<double> mode_values(const ModeFn& f, const Table& t, const Experiment& ex) {
  const int ai = axis_index(t, "theta_i"), ao = axis_index(t, "theta_o"), ak = axis_index(t, "k"), ac = axis_index(t, "channel");
  static const GaussLegendre gl(8);
  std::vector<double> v(t.cells());
  for_each_cell(t, [&](std::size_t flat, const std::vector<std::size_t>& idx) {
    const double c = ex.spheres.albedo[static_cast<int>(t.axes[ac].values[idx[ac]])];
    const int k = static_cast<int>(t.axes[ak].values[idx[ak]]);
    const double mu_i = std::cos(t.axes[ai].values[idx[ai]]);
    const Axis& o = t.axes[ao];
    const double mu_hi = std::cos(o.lower(idx[ao])), mu_lo = std::cos(o.upper(idx[ao]));
    double num = 0, den = 0;
    for (std::size_t a = 0; a < gl.x.size(); ++a) {
      const double mu = 0.5 * (mu_lo + mu_hi) + 0.5 * (mu_hi - mu_lo) * gl.x[a];
      num += gl.w[a] * mu * f(c, mu_i, mu, k);
      den += gl.w[a] * mu;
    }
    v[flat] = num / den;
  });
  return v;
}

std::vector<double> kd_values(const std::string& model, const Table& t, const Experiment& ex) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, double>, double> memo;
  const int ac = axis_index(t, "channel");
  std::vector<double> v(t.cells());
  for_each_cell(t, [&](std::size_t flat, const std::vector<std::size_t>& idx) {
    const double c = ex.spheres.albedo[static_cast<int>(t.axes[ac].values[idx[ac]])];
    {
      std::lock_guard<std::mutex> lock(mutex);
      const auto it = memo.find({model, c});
      if (it != memo.end()) {
        v[flat] = it->second;
        return;
      }
    }
    double kd;
    if (model == "kd_eq40") kd = ls::kd_from_albedo(c);
    else if (model == "kd_eq30") {
      const ls::Brdf& b = deon(c, 0);
      kd = ls::spherical_albedo([&b](double mi, double mo) { return b.zeroth_mode(mi, mo); });
    } else if (model == "kd_reference_three_term") kd = ls::spherical_albedo_reference(std::min(c, 0.9999));
    else throw std::invalid_argument("no sphere k_d model " + model);
    std::lock_guard<std::mutex> lock(mutex);
    v[flat] = memo[{model, c}] = kd;
  });
  return v;
}

std::vector<double> evaluate(const std::string& model, const Table& t, const Experiment& ex) {
  if (model == "phase_eq1") return phase_values(t);
  if (model == "phase_three_term") return phase_three_term_values(t);
  if (t.quantity == "brdf_modes") return mode_values(mode_model(model), t, ex);
  if (t.quantity == "spherical_albedo") return kd_values(model, t, ex);
  if (model == "volumetric_mc") return volumetric_table(t, ex).values();
  if (model == "albedo_reference_three_term") return albedo_values(brdf_model("reference_three_term"), t, ex);
  if (model == "albedo_deon_corrected") return albedo_values(brdf_model("deon_corrected"), t, ex);
  return brdf_values(brdf_model(model), t, ex);
}

// volumetric_mc is a simulation itself: its standard errors enter the checks in
// quadrature (validate/metrics.h); the other models have no noise of their own.
std::vector<double> evaluate_stderr(const std::string& model, const Table& t, const Experiment& ex,
                                    const std::vector<double>&) {
  if (model != "volumetric_mc") return {};
  return volumetric_table(t, ex).stderrs();
}

std::string unsupported(const std::string& model, const Experiment& ex) {
  if (model == "single_scattering_eq10" && ex.spheres.placement != SpherePlacement::volumetric)
    return "single_scattering_eq10 is exact only for placement = \"volumetric\"; use single_scattering_eq10_dilute";
  return "";
}

}  // namespace

const ModelFamily& sphere_models() {
  static const ModelFamily family{model_list(), evaluate, evaluate_stderr, unsupported};
  return family;
}

}  // namespace mcref
