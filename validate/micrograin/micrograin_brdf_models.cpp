// Models of the micrograin_brdf family (issue #3): LRPB23 Eq. 1–2 and the
// later paper's form (vNDF paper Eq. 1), evaluated on brdf tables as
// cosine-weighted bin averages over (cos theta_o, phi) cells, per RGB channel,
// and on albedo / delta tables as directional energies. None is exact for the
// explicit geometry (all are single-scattering models, and their masking
// terms approximate the true visibility); see micrograin_bsdf.h.
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "models/micrograin/micrograin_bsdf.h"
#include "sim/tally/brdf_tally.h"
#include "validate/micrograin/brdf_cell_rule.h"
#include "validate/micrograin/geometry_memo.h"
#include "validate/micrograin/micrograin_brdf_value.h"
#include "validate/micrograin/simulated_pore_base.h"
#include "validate/model_evaluation.h"

namespace mcref {

namespace mg = micrograin;

namespace {

mg::MicroSurface channel_of(const MicroBrdf& b, int k) {
  mg::MicroSurface s;
  switch (b.type) {
    case MicroBrdf::Type::Black: s.type = mg::MicroSurface::Type::Black; break;
    case MicroBrdf::Type::Lambertian: s.type = mg::MicroSurface::Type::Lambertian; break;
    case MicroBrdf::Type::Conductor: s.type = mg::MicroSurface::Type::Conductor; break;
    case MicroBrdf::Type::RoughConductor: s.type = mg::MicroSurface::Type::RoughConductor; break;
    case MicroBrdf::Type::DiffuseSpecular: s.type = mg::MicroSurface::Type::DiffuseSpecular; break;
  }
  s.kd = b.albedo[k];
  s.eta = b.eta[k];
  s.kappa = b.kappa[k];
  s.ior = b.ior;
  s.alpha = b.alpha;
  return s;
}

struct Spec {
  enum class Part { Grain, Base, Total } part;
  enum class Form { Lrpb23, Gdist } form;
  mg::LambdaMethod lambda = mg::LambdaMethod::Quadrature;
  bool simulated_vp = false;  // base term with V_p(i, o) measured (validate/micrograin/simulated_pore_base.h)
  mg::TwoWay masking = mg::TwoWay::Product;  // two-direction masking of the Gdist form (issue #15)
  mg::SmithG2 g2 = mg::SmithG2::HeightCorrelated;  // reading of LRPB23 Eq. 2's G (issue #15)
};

const std::map<std::string, Spec>& specs() {
  using P = Spec::Part;
  using F = Spec::Form;
  using L = mg::LambdaMethod;
  static const std::map<std::string, Spec> s{
      {"lrpb23_series4", {P::Total, F::Lrpb23, L::Series4}},
      {"lrpb23_quadrature", {P::Total, F::Lrpb23, L::Quadrature}},
      {"lrpb23_ggx", {P::Total, F::Lrpb23, L::GgxEquivalent}},
      {"lrpb23_grain_series4", {P::Grain, F::Lrpb23, L::Series4}},
      {"lrpb23_grain_quadrature", {P::Grain, F::Lrpb23, L::Quadrature}},
      {"lrpb23_grain_ggx", {P::Grain, F::Lrpb23, L::GgxEquivalent}},
      {"lrpb23_separable", {P::Total, F::Lrpb23, L::Quadrature, false, mg::TwoWay::Product, mg::SmithG2::Separable}},
      {"lrpb23_grain_separable",
       {P::Grain, F::Lrpb23, L::Quadrature, false, mg::TwoWay::Product, mg::SmithG2::Separable}},
      {"lrpb23_base", {P::Base, F::Lrpb23}},
      {"gdist_grain", {P::Grain, F::Gdist}},
      {"gdist_total", {P::Total, F::Gdist}},
      {"lrpb23_albedo_quadrature", {P::Total, F::Lrpb23, L::Quadrature}},
      {"gdist_albedo", {P::Total, F::Gdist}},
      {"gdist_base_simvp", {P::Base, F::Gdist, L::Quadrature, true}},
      {"gdist_total_simvp", {P::Total, F::Gdist, L::Quadrature, true}},
      {"gdist_albedo_simvp", {P::Total, F::Gdist, L::Quadrature, true}},
      {"gdist_base_union", {P::Base, F::Gdist, L::Quadrature, false, mg::TwoWay::Union}},
      {"gdist_grain_union", {P::Grain, F::Gdist, L::Quadrature, false, mg::TwoWay::Union}},
      {"gdist_total_union", {P::Total, F::Gdist, L::Quadrature, false, mg::TwoWay::Union}},
      {"gdist_albedo_union", {P::Total, F::Gdist, L::Quadrature, false, mg::TwoWay::Union}},
  };
  return s;
}

std::vector<ModelInfo> model_list() {
  std::vector<ModelInfo> m{
      {"lrpb23_series4", "brdf", false, "LRPB23 Eq. 1-2, G = 1/(1+Lambda_i+Lambda_o), Lambda by the series n = 4 (Eq. 25)", "micrograin", "total"},
      {"lrpb23_quadrature", "brdf", false, "LRPB23 Eq. 1-2, Lambda by quadrature of the exact NDF", "micrograin", "total"},
      {"lrpb23_ggx", "brdf", false, "LRPB23 Eq. 1-2, Lambda of GGX at alpha~ (Eq. 18)", "micrograin", "total"},
      {"lrpb23_grain_series4", "brdf", false, "LRPB23 w+ f^S (Eq. 1-2, 24), Lambda series n = 4", "micrograin", "order1_grain"},
      {"lrpb23_grain_quadrature", "brdf", false, "LRPB23 w+ f^S, Lambda by quadrature", "micrograin", "order1_grain"},
      {"lrpb23_grain_ggx", "brdf", false, "LRPB23 w+ f^S, Lambda of GGX at alpha~", "micrograin", "order1_grain"},
      {"lrpb23_separable", "brdf", false,
       "LRPB23 Eq. 1-2 read with the separable G = G1(i) G1(o) (Heitz 2014 Eq. 98), Lambda by quadrature", "micrograin",
       "total"},
      {"lrpb23_grain_separable", "brdf", false,
       "LRPB23 w+ f^S with the separable G = G1(i) G1(o), Lambda by quadrature (the other reading of Eq. 2; issue #15)",
       "micrograin", "order1_grain"},
      {"lrpb23_base", "brdf", false,
       "(1 - w+) f^B (LRPB23 Eq. 1, 24) = (1 - tau0) V(i) V(o) f_B (vNDF Eq. 1, independent pore visibilities)", "micrograin",
       "order1_base"},
      {"gdist_grain", "brdf", false,
       "tau0 f_S (vNDF Eq. 1): single scattering on grains, D of Eq. 2, G_dist(i,h) G_dist(o,h) (Eq. 3)", "micrograin",
       "order1_grain"},
      {"gdist_total", "brdf", false, "tau0 f_S + V_p f_B (vNDF Eq. 1), G_dist product, independent V_p", "micrograin", "total"},
      {"lrpb23_albedo_quadrature", "albedo", false,
       "directional albedo of LRPB23 Eq. 1-2 (Lambda by quadrature), delta lobe included, and of its grain and base "
       "parts (order-1 components); delta table: its delta energy",
       "micrograin", ""},
      {"gdist_albedo", "albedo", false,
       "directional albedo of vNDF Eq. 1 with G_dist, delta lobe included, and of its grain and base parts (order-1 "
       "components)",
       "micrograin", ""},
      {"gdist_base_simvp", "brdf", false,
       "(1 - tau0) V_p(i, o) f_B (vNDF Eq. 1) with the bidirectional pore visibility V_p measured on an explicit field: "
       "a cross-check of gdist_base_union's closed form, up to its own Monte Carlo noise (~1 %), which enters z",
       "micrograin", "order1_base"},
      {"gdist_total_simvp", "brdf", false,
       "tau0 f_S with G_dist + (1 - tau0) V_p(i, o) f_B with V_p measured (vNDF Eq. 1; its noise enters z): a "
       "cross-check of the base term of gdist_total_union",
       "micrograin", "total"},
      {"gdist_albedo_simvp", "albedo", false,
       "directional albedo of vNDF Eq. 1 with G_dist and V_p(i, o) measured (its noise enters z); grain and base "
       "parts in the order-1 components",
       "micrograin", ""},
      {"gdist_base_union", "brdf", true,
       "(1 - tau0) V_p(i, o) f_B (vNDF Eq. 1) with V_p = exp(-rho (|K_i U K_o| - pi)) in closed form: exact for a "
       "single event on the base (issue #15)",
       "micrograin", "order1_base"},
      {"gdist_grain_union", "brdf", true,
       "tau0 f_S (vNDF Eq. 1) with the two-direction masking G_dist(i, o, h) = exp(-rho (|K_i(h) U K_o(h)| - "
       "sigma(n, h))): exact for a single event on a grain (issue #15)",
       "micrograin", "order1_grain"},
      {"gdist_total_union", "brdf", false, "tau0 f_S + V_p f_B (vNDF Eq. 1), both with the union masking (single scattering)",
       "micrograin", "total"},
      {"gdist_albedo_union", "albedo", false,
       "directional albedo of vNDF Eq. 1 with the union masking, delta lobe included, and of its grain and base parts "
       "(order-1 components)",
       "micrograin", ""},
  };
  return m;
}

// f of one model for all channels.
void eval_f(const Spec& s, const mg::GrainField& f, const MicrograinMaterials& mat, Vec3 i, Vec3 o, double out[3]) {
  // The G_dist diffuse and specular geometries are channel-independent: computed once
  // (the diffuse one once for all models of a table: geometry_memo.h).
  double geometry = -1, specular_geometry = -1;
  auto specular = [&](const mg::MicroSurface& g) {
    if (!mg::has_specular_lobe(g)) return 0.0;
    if (specular_geometry < 0) specular_geometry = mg::gdist_specular_geometry(f, i, o, s.masking);
    return specular_geometry * mg::specular_fresnel(g, dot(i, normalize(i + o))) / (4 * i.z * o.z);
  };
  for (int k = 0; k < 3; ++k) {
    const mg::MicroSurface g = channel_of(mat.grain, k);
    const mg::MicroSurface b = channel_of(mat.base, k);
    double v = 0;
    if (s.part != Spec::Part::Base) {
      if (s.form == Spec::Form::Lrpb23) {
        v += mg::lrpb23_grain_part(f, g, i, o, s.lambda, s.g2);
      } else if (g.type == mg::MicroSurface::Type::Lambertian || g.type == mg::MicroSurface::Type::DiffuseSpecular) {
        const bool lambert = g.type == mg::MicroSurface::Type::Lambertian;
        if (geometry < 0) geometry = memo_diffuse_geometry(f, i, o, lambert ? 0.0 : g.ior, s.masking);
        if (lambert) {
          v += g.kd * geometry;
        } else {
          v += mg::body_factor(g) * geometry + specular(g);
        }
      } else {
        v += specular(g);  // conductor grains
      }
    }
    if (s.part != Spec::Part::Grain) v += mg::gdist_base_part(f, b, i, o, s.masking);
    out[k] = v;
  }
}

// The cell rule's tolerance (brdf_cell_rule.h): half of kCellRelTolerance, and a
// floor of 1e-12 sr^-1 on a cell's average f (cells at zero; model_evaluation.h).
CellRuleTolerance cell_tolerance(double t0, double t1, double p0, double p1) {
  const double cos_sin = 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) * std::fabs(p1 - p0);
  return {0.5 * kCellRelTolerance, 1e-12 * cos_sin};
}

// The cell rule's accuracy over a table (one entry per task), to the caller's
// ModelAccuracyScope: on the calling thread, after the parallel loop.
void report_accuracy(const std::vector<ModelAccuracy>& per_task) {
  ModelAccuracy all;
  for (const ModelAccuracy& a : per_task) all.merge(a);
  report_model_accuracy(all);
}

// g = f cos theta_o sin theta_o of parts[p] in components 3p..3p+2, phi relative to phi_i.
template <int N>
auto cosine_weighted(const std::array<Spec, N / 3>& parts, const mg::GrainField& f, const MicrograinMaterials& mat,
                     Vec3 wi, double phi_i) {
  return [&parts, &f, &mat, wi, phi_i](double theta, double phi, double* out) {
    const Vec3 wo = spherical_direction(theta, phi_i + phi);
    const double w = std::cos(theta) * std::sin(theta);
    for (int p = 0; p < N / 3; ++p) {
      eval_f(parts[p], f, mat, wi, wo, out + 3 * p);
      for (int k = 0; k < 3; ++k) out[3 * p + k] *= w;
    }
  };
}

std::vector<double> evaluate_brdf(const Spec& s, const Table& t, const Experiment& ex, const mg::GrainField& f) {
  std::vector<double> out(t.cells(), NAN);
  const Axis &ti = t.axes[0], &pi = t.axes[1], &to = t.axes[2], &ph = t.axes[3];
  const std::array<Spec, 1> parts{s};
  const CellsDone done = cell_progress();  // read here: the tasks below run on other threads
  std::vector<ModelAccuracy> accuracy(ti.size() * pi.size() * to.size());
  // One task per (theta_i, phi_i, theta_o) row of cells; each writes only its own cells.
  tbb::parallel_for(std::size_t{0}, accuracy.size(), [&](std::size_t row) {
    const std::size_t a = row / (pi.size() * to.size()), b = row / to.size() % pi.size(), c = row % to.size();
    const Vec3 wi = spherical_direction(ti.values[a], pi.values[b]);
    const auto g = cosine_weighted<3>(parts, f, ex.materials, wi, pi.values[b]);
    const double t0 = to.lower(c), t1 = to.upper(c);
    for (std::size_t d = 0; d < ph.size(); ++d) {
      const double p0 = ph.lower(d), p1 = ph.upper(d);
      const double den = 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) * (p1 - p0);  // ∫∫ cos sin
      const CellRuleTolerance tol = cell_tolerance(t0, t1, p0, p1);
      const CellRuleResult<3> num = cell_rule<3>(g, ti.values[a], t0, t1, p0, p1, tol);
      for (std::size_t k = 0; k < 3; ++k) out[t.index({a, b, c, d, k})] = num.value[k] / den;
      accuracy[row].add(t.index({a, b, c, d, 0}), num.rel_error, num.converged, tol.rel);
    }
    done(ph.size() * 3);
  });
  report_accuracy(accuracy);
  return out;
}

std::vector<double> evaluate_albedo(const Spec& s, const Table& t, const Experiment& ex, const mg::GrainField& f) {
  std::vector<double> out(t.cells(), NAN);
  const bool delta_table = is_delta_table(t.name);
  const Axis &ti = t.axes[0], &pi = t.axes[1];
  const std::size_t total = t.axes[2].size() - 1, grain_component = 0, base = 1;  // order1_grain, order1_base
  const CellsDone done = cell_progress();
  const std::size_t cells_per_direction = t.cells() / (ti.size() * pi.size());
  std::vector<ModelAccuracy> accuracy(ti.size() * pi.size());
  // One task per incident direction; each writes only its own cells.
  tbb::parallel_for(std::size_t{0}, accuracy.size(), [&](std::size_t dir) {
    const std::size_t a = dir / pi.size(), b = dir % pi.size();
    const Vec3 wi = spherical_direction(ti.values[a], pi.values[b]);
    double delta[3];
    for (int k = 0; k < 3; ++k) delta[k] = mg::gdist_base_delta_energy(f, channel_of(ex.materials.base, k), wi, s.masking);
    if (delta_table) {
      for (std::size_t k = 0; k < 3; ++k) {
        out[t.index({a, b, base, k})] = delta[k];
        out[t.index({a, b, total, k})] = delta[k];
      }
      done(cells_per_direction);
      return;
    }
    // Energy of the grain part and of the base part (order-1 components of
    // the table), so that a model's error splits into its order-1 terms and
    // the multiple scattering it leaves out: the cell rule over the hemisphere
    // (isotropic fields: phi in [0, pi], twice), 4 x 4 pieces to start with.
    const double span = ex.isotropic ? kPi : 2 * kPi;
    const std::array<Spec, 2> parts{Spec{Spec::Part::Grain, s.form, s.lambda, false, s.masking, s.g2},
                                    Spec{Spec::Part::Base, s.form, s.lambda, false, s.masking, s.g2}};
    const CellRuleTolerance tol = cell_tolerance(0.0, kPi / 2, 0.0, span);
    const CellRuleResult<6> energy = cell_rule<6>(cosine_weighted<6>(parts, f, ex.materials, wi, pi.values[b]),
                                                  ti.values[a], 0.0, kPi / 2, 0.0, span, tol, 4, 4);
    const double fold = ex.isotropic ? 2 : 1;
    for (std::size_t k = 0; k < 3; ++k) {
      const double grain_energy = fold * energy.value[k], base_energy = fold * energy.value[3 + k] + delta[k];
      out[t.index({a, b, grain_component, k})] = grain_energy;
      out[t.index({a, b, base, k})] = base_energy;
      out[t.index({a, b, total, k})] = grain_energy + base_energy;
    }
    accuracy[dir].add(t.index({a, b, 0, 0}), energy.rel_error, energy.converged, tol.rel);
    done(cells_per_direction);
  });
  report_accuracy(accuracy);
  return out;
}

// The Gdist form with the measured V_p: the grain part as gdist_*, the base
// part from simulated_pore_base.
const PoreBase& measured_pore_base(const Table& t, const Experiment& ex) {
  const MicrograinMaterials& mat = ex.materials;
  const BaseReflection base{
      [&](int ch, Vec3 i, Vec3 o) { return mg::flat_brdf(channel_of(mat.base, ch), i, o); },
      [&](int ch, Vec3 i) { return mg::flat_delta_energy(channel_of(mat.base, ch), i.z); }};
  return simulated_pore_base(t, ex, base);
}

std::vector<double> evaluate_simulated_vp(const Spec& s, const Table& t, const Experiment& ex, const mg::GrainField& f) {
  std::vector<double> out = measured_pore_base(t, ex).values;
  if (s.part == Spec::Part::Base) return out;
  const Spec grain{Spec::Part::Grain, Spec::Form::Gdist};
  if (t.quantity == "brdf") {
    const std::vector<double> g = evaluate_brdf(grain, t, ex, f);
    for (std::size_t k = 0; k < out.size(); ++k) out[k] += g[k];
    return out;
  }
  const bool delta_table = is_delta_table(t.name);
  if (delta_table) return out;
  const std::vector<double> g = evaluate_albedo(grain, t, ex, f);  // its order1_grain component
  const Axis &ti = t.axes[0], &pi = t.axes[1];
  const std::size_t grain_component = 0, total = t.axes[2].size() - 1;
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < pi.size(); ++b)
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t gi = t.index({a, b, grain_component, k});
        out[gi] = g[gi];
        out[t.index({a, b, total, k})] += g[gi];
      }
  return out;
}

std::vector<double> evaluate(const std::string& model, const Table& t, const Experiment& ex) {
  const auto it = specs().find(model);
  if (it == specs().end()) throw std::invalid_argument("no model " + model);
  const MicrograinGeometry& geo = ex.micrograin;
  const mg::GrainField f{geo.tau0, geo.beta_x, geo.beta_y};
  if (it->second.simulated_vp) return evaluate_simulated_vp(it->second, t, ex, f);
  if (t.quantity == "brdf") return evaluate_brdf(it->second, t, ex, f);
  if (t.quantity == "albedo") return evaluate_albedo(it->second, t, ex, f);
  throw std::invalid_argument("model " + model + " does not predict " + t.quantity);
}

// The measured-V_p models carry the noise of that measurement (the grain
// part is analytic; its cells have no measured error: NaN, read as 0).
std::vector<double> evaluate_stderr(const std::string& model, const Table& t, const Experiment& ex,
                                    const std::vector<double>&) {
  const auto it = specs().find(model);
  if (it == specs().end() || !it->second.simulated_vp || !ex.materials.configured) return {};
  return measured_pore_base(t, ex).stderrs;
}

std::string unsupported(const std::string& model, const Experiment& ex) {
  const auto it = specs().find(model);
  if (it == specs().end()) return "no model " + model;
  if (!ex.materials.configured) return "model " + model + " needs [material]";
  if (ex.micrograin.anisotropic() && it->second.form == Spec::Form::Lrpb23)
    return "model " + model + " is defined for isotropic grains only (beta_x = beta_y)";
  // The grain term (LRPB23 Eq. 2, vNDF Eq. 1) is written for smooth or diffuse
  // grains; rough-conductor grains would give 0 there, silently.
  if (it->second.part != Spec::Part::Base && ex.materials.grain.type == MicroBrdf::Type::RoughConductor)
    return "model " + model + " has no grain term for rough_conductor grains (black, lambertian, conductor or "
           "diffuse_specular)";
  return "";
}

}  // namespace

void micrograin_brdf_value(const std::string& model, const Experiment& ex, Vec3 i, Vec3 o, double out[3]) {
  const auto it = specs().find(model);
  if (it == specs().end() || it->second.simulated_vp) throw std::invalid_argument("no analytic model " + model);
  const MicrograinGeometry& geo = ex.micrograin;
  eval_f(it->second, mg::GrainField{geo.tau0, geo.beta_x, geo.beta_y}, ex.materials, i, o, out);
}

const ModelFamily& micrograin_brdf_models() {
  static const ModelFamily family{model_list(), evaluate, evaluate_stderr, unsupported};
  return family;
}

}  // namespace mcref
