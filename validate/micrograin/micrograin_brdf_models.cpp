// Models of the micrograin_brdf family (issue #3): LRPB23 Eq. 1–2 and the
// later paper's form (vNDF paper Eq. 1), evaluated on brdf tables as
// cosine-weighted bin averages over (cos theta_o, phi) cells, per RGB channel,
// and on albedo / delta tables as directional energies. None is exact for the
// explicit geometry (all are single-scattering models, and their masking
// terms approximate the true visibility); see micrograin_bsdf.h.
#include <cmath>
#include <map>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "models/core/quadrature.h"
#include "models/micrograin/micrograin_bsdf.h"
#include "sim/tally/brdf_tally.h"
#include "validate/micrograin/geometry_memo.h"
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

// f of one model for all channels; sharp_only: the grains' specular lobe alone
// (the part whose peak a coarse cell rule can miss; issue #15, part 5).
void eval_f(const Spec& s, const mg::GrainField& f, const MicrograinMaterials& mat, Vec3 i, Vec3 o, double out[3],
            bool sharp_only = false) {
  // The G_dist diffuse and specular geometries are channel-independent: computed once
  // (the diffuse one once for all models of a table: geometry_memo.h).
  double geometry = -1, specular_geometry = -1;
  auto specular = [&](const mg::MicroSurface& g) {
    if (!mg::has_specular_lobe(g)) return 0.0;
    if (specular_geometry < 0) specular_geometry = mg::gdist_specular_geometry(f, i, o, s.masking);
    return specular_geometry * mg::specular_fresnel(g, dot(i, normalize(i + o))) / (4 * i.z * o.z);
  };
  for (int k = 0; k < 3; ++k) {
    mg::MicroSurface g = channel_of(mat.grain, k);
    const mg::MicroSurface b = channel_of(mat.base, k);
    double v = 0;
    if (sharp_only) {
      if (s.part != Spec::Part::Base && g.type != mg::MicroSurface::Type::Lambertian) {
        g.kd = 0;  // diffuse + specular grains: the specular lobe alone (LRPB23 form)
        v = s.form == Spec::Form::Lrpb23 ? mg::lrpb23_grain_part(f, g, i, o, s.lambda, s.g2)
                                         : specular(g);
      }
      out[k] = v;
      continue;
    }
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

// ∫∫ f mu dmu dphi of one model over [mu0, mu1] x [p0, p1] by an n x n product rule.
void cell_integral(const Spec& s, const mg::GrainField& f, const MicrograinMaterials& mat, Vec3 wi, double phi_i,
                   double mu0, double mu1, double p0, double p1, const GaussLegendre& g, bool sharp_only, double out[3]) {
  out[0] = out[1] = out[2] = 0;
  const std::size_t n = g.x.size();
  for (std::size_t u = 0; u < n; ++u)
    for (std::size_t v = 0; v < n; ++v) {
      const double mu = 0.5 * (mu0 + mu1) + 0.5 * (mu1 - mu0) * g.x[u];
      const double phi = 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * g.x[v];
      const double w = 0.25 * (mu1 - mu0) * (p1 - p0) * g.w[u] * g.w[v] * mu;
      const Vec3 wo = spherical_direction(std::acos(std::fmin(1.0, mu)), phi_i + phi);
      double fv[3];
      eval_f(s, f, mat, wi, wo, fv, sharp_only);
      for (int k = 0; k < 3; ++k) out[k] += w * fv[k];
    }
}

// The sharp part's cell integral, refined by quadrisection until the children
// agree with their parent to tol (halved per level, at most `depth` levels; the
// caller asks 1e-5 of the cell's integral, far below the simulation's error bars).
void sharp_cell_integral(const Spec& s, const mg::GrainField& f, const MicrograinMaterials& mat, Vec3 wi, double phi_i,
                         double mu0, double mu1, double p0, double p1, const double whole[3], double tol, int depth,
                         double out[3]) {
  static const GaussLegendre g(4);
  const double mm = 0.5 * (mu0 + mu1), pm = 0.5 * (p0 + p1);
  const double box[4][4] = {{mu0, mm, p0, pm}, {mm, mu1, p0, pm}, {mu0, mm, pm, p1}, {mm, mu1, pm, p1}};
  double child[4][3], sum[3] = {0, 0, 0};
  for (int c = 0; c < 4; ++c) {
    cell_integral(s, f, mat, wi, phi_i, box[c][0], box[c][1], box[c][2], box[c][3], g, true, child[c]);
    for (int k = 0; k < 3; ++k) sum[k] += child[c][k];
  }
  double diff = 0;
  for (int k = 0; k < 3; ++k) diff = std::fmax(diff, std::fabs(sum[k] - whole[k]));
  if (depth <= 0 || diff <= tol) {
    for (int k = 0; k < 3; ++k) out[k] = sum[k];
    return;
  }
  out[0] = out[1] = out[2] = 0;
  for (int c = 0; c < 4; ++c) {
    double r[3];
    sharp_cell_integral(s, f, mat, wi, phi_i, box[c][0], box[c][1], box[c][2], box[c][3], child[c], 0.5 * tol, depth - 1, r);
    for (int k = 0; k < 3; ++k) out[k] += r[k];
  }
}

std::vector<double> evaluate_brdf(const Spec& s, const Table& t, const Experiment& ex, const mg::GrainField& f) {
  std::vector<double> out(t.cells(), NAN);
  const Axis &ti = t.axes[0], &pi = t.axes[1], &to = t.axes[2], &ph = t.axes[3];
  const int n = s.form == Spec::Form::Gdist ? 3 : 6;
  const GaussLegendre g(n);
  // Grains with a specular lobe: a fixed n x n rule can miss its peak in a
  // coarse cell (at theta_i = 89 deg it gave 0.04 for 1.20 in a 45 x 180 deg
  // cell; issue #15, part 5). That lobe alone is then integrated adaptively
  // and replaces its share of the fixed rule; the smooth rest keeps the n x n rule.
  const MicroBrdf::Type grain = ex.materials.grain.type;
  const bool sharp = s.part != Spec::Part::Base &&
                     (grain == MicroBrdf::Type::Conductor || grain == MicroBrdf::Type::DiffuseSpecular);
  const CellsDone done = cell_progress();  // read here: the tasks below run on other threads
  // One task per (theta_i, phi_i, theta_o) row of cells; each writes only its own cells.
  tbb::parallel_for(std::size_t{0}, ti.size() * pi.size() * to.size(), [&](std::size_t row) {
    const std::size_t a = row / (pi.size() * to.size()), b = row / to.size() % pi.size(), c = row % to.size();
    const Vec3 wi = spherical_direction(ti.values[a], pi.values[b]);
    const double mu0 = std::cos(to.upper(c)), mu1 = std::cos(to.lower(c));
    for (std::size_t d = 0; d < ph.size(); ++d) {
      const double p0 = ph.lower(d), p1 = ph.upper(d);
      const double den = 0.5 * (mu1 * mu1 - mu0 * mu0) * (p1 - p0);  // ∫∫ mu dmu dphi
      double num[3];
      cell_integral(s, f, ex.materials, wi, pi.values[b], mu0, mu1, p0, p1, g, false, num);
      if (sharp) {
        double coarse[3], start[3], fine[3];
        cell_integral(s, f, ex.materials, wi, pi.values[b], mu0, mu1, p0, p1, g, true, coarse);
        static const GaussLegendre g4(4);
        cell_integral(s, f, ex.materials, wi, pi.values[b], mu0, mu1, p0, p1, g4, true, start);
        const double scale = std::fmax(std::fabs(num[0]), std::fmax(std::fabs(num[1]), std::fabs(num[2])));
        sharp_cell_integral(s, f, ex.materials, wi, pi.values[b], mu0, mu1, p0, p1, start, 1e-5 * scale + 1e-300, 7, fine);
        for (int k = 0; k < 3; ++k) num[k] += fine[k] - coarse[k];
      }
      for (std::size_t k = 0; k < 3; ++k) out[t.index({a, b, c, d, k})] = num[k] / den;
    }
    done(ph.size() * 3);
  });
  return out;
}

std::vector<double> evaluate_albedo(const Spec& s, const Table& t, const Experiment& ex, const mg::GrainField& f) {
  std::vector<double> out(t.cells(), NAN);
  const bool delta_table = is_delta_table(t.name);
  const Axis &ti = t.axes[0], &pi = t.axes[1];
  const std::size_t total = t.axes[2].size() - 1, grain_component = 0, base = 1;  // order1_grain, order1_base
  const GaussLegendre gm(24), gp(24);
  const CellsDone done = cell_progress();
  const std::size_t cells_per_direction = t.cells() / (ti.size() * pi.size());
  // One task per incident direction; each writes only its own cells.
  tbb::parallel_for(std::size_t{0}, ti.size() * pi.size(), [&](std::size_t dir) {
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
    // the multiple scattering it leaves out.
    double e[2][3] = {{0, 0, 0}, {0, 0, 0}};
    const double span = ex.isotropic ? kPi : 2 * kPi;
    const Spec grain{Spec::Part::Grain, s.form, s.lambda, false, s.masking, s.g2};
    const Spec base_part{Spec::Part::Base, s.form, s.lambda, false, s.masking, s.g2};
    for (std::size_t u = 0; u < gm.x.size(); ++u)
      for (std::size_t v = 0; v < gp.x.size(); ++v) {
        const double mu = 0.5 + 0.5 * gm.x[u], phi = 0.5 * span * (1 + gp.x[v]);
        const Vec3 wo = spherical_direction(std::acos(mu), pi.values[b] + phi);
        const double w = 0.5 * gm.w[u] * 0.5 * span * gp.w[v] * mu * (ex.isotropic ? 2 : 1);
        double fg[3], fb[3];
        eval_f(grain, f, ex.materials, wi, wo, fg);
        eval_f(base_part, f, ex.materials, wi, wo, fb);
        for (int k = 0; k < 3; ++k) {
          e[0][k] += w * fg[k];
          e[1][k] += w * fb[k];
        }
      }
    for (std::size_t k = 0; k < 3; ++k) {
      out[t.index({a, b, grain_component, k})] = e[0][k];
      out[t.index({a, b, base, k})] = e[1][k] + delta[k];
      out[t.index({a, b, total, k})] = e[0][k] + e[1][k] + delta[k];
    }
    done(cells_per_direction);
  });
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
  return "";
}

}  // namespace

const ModelFamily& micrograin_brdf_models() {
  static const ModelFamily family{model_list(), evaluate, evaluate_stderr, unsupported};
  return family;
}

}  // namespace mcref
