// Models of microflake slabs (SpongeCake, issue #4), evaluated on the cells
// of the slab tables as the tally bins them: cosine-weighted averages over
// each (|cos theta_o|, phi) bin, per RGB channel.
//
//  spongecake_ss_brdf / _btdf   single scattering, Eq. 8-16 (any stack), on the order1_volume tables
//  spongecake_ss_substrate      single scattering + substrate seen through the stack (Sec. 4.5),
//                               explicit check on the total table of a max_order = 1 run
//  chandrasekhar_isotropic      a H(mu_i) H(mu_o) / (4 pi (mu_i + mu_o)), all orders, one isotropic
//                               layer as a half-space; explicit check on the total table
//  white_furnace                scattered energy of a conservative stack = 1 - T_delta(wi)
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

#include "models/core/quadrature.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/radiative_transfer/isotropic.h"
#include "models/sggx/single_scattering.h"
#include "sim/slab/slab_geometry.h"
#include "validate/model_evaluation.h"

namespace mcref {

namespace {

std::vector<ModelInfo> slab_model_list() {
  std::vector<ModelInfo> m{
      {"spongecake_ss_brdf", "brdf", true,
       "SpongeCake single scattering, reflection (Wang et al. 2022 Eq. 8-12, layers Sec. 4.4)", "slab", "order1_volume"},
      {"spongecake_ss_btdf", "btdf", true,
       "SpongeCake single scattering, transmission (Eq. 15-16 with |cos|, layers Sec. 4.4)", "slab", "order1_volume"},
      {"spongecake_ss_substrate", "brdf", true,
       "single scattering of the layers + substrate seen through the stack (Sec. 4.5); for max_order = 1 totals",
       "slab", "order1_total"},
      {"chandrasekhar_isotropic", "brdf", true,
       "isotropic half-space, all orders: a H(mu_i) H(mu_o) / (4 pi (mu_i + mu_o)) (Chandrasekhar 1960)", "slab",
       "total_half_space"},
      {"white_furnace", "energy_balance", true,
       "conservative stack: R + T_scattered = 1 - exp(-sum_k tau_k sigma_k(wi) / mu_i) (SpongeCake Fig. 21)", "slab"},
  };
  return m;
}

// One channel of a layer as a SpongeCake model layer (optical thickness kept).
sggx::Layer model_layer(const SlabLayer& l, int c) {
  const double T = l.thickness, rho = l.density * l.profile.mean();
  switch (l.phase) {
    case SlabPhase::kSggxSurface: return sggx::sggx_layer(T, rho, sggx::surface_like(l.alpha, l.orientation), l.albedo[c], l.f0[c]);
    case SlabPhase::kSggxFiber: return sggx::sggx_layer(T, rho, sggx::fiber_like(l.alpha, l.orientation), l.albedo[c], l.f0[c]);
    case SlabPhase::kHenyeyGreenstein: return sggx::hg_layer(T, rho, l.g, l.albedo[c]);
    default: return sggx::isotropic_layer(T, rho, l.albedo[c]);
  }
}

// Single scattering of a stack for one channel, light from the top. A stack
// without Lambert-sphere layers is SpongeCake's (Sec. 4.4); with them (no
// SpongeCake layer type: sigma = 1, reduced phase albedo p_LS, d'Eon Eq. 1),
// the same sum over layers (Eq. 8-16), each layer with its own sigma(w) and
// reduced phase, attenuated by the layers crossed before and after it.
double single_scattering(const SlabGeometry& g, int c, Vec3 wi, Vec3 wo) {
  bool generic = false;
  for (const SlabLayer& l : g.layers) generic = generic || l.phase == SlabPhase::kLambertSphere;
  if (!generic) {
    std::vector<sggx::Layer> stack;
    for (const SlabLayer& l : g.layers) stack.push_back(model_layer(l, c));
    return sggx::single_scattering_bsdf(stack, wi, wo);
  }
  const double mi = std::fabs(wi.z), mo = std::fabs(wo.z);
  const bool reflection = (wi.z > 0) == (wo.z > 0);
  if (!(mi > 0) || !(mo > 0) || !(wi.z > 0)) return 0;
  const std::size_t n = g.layers.size();
  std::vector<double> tau(n), li(n), lo(n), reduced(n);  // Lambda = sigma(w)/mu per layer
  for (std::size_t k = 0; k < n; ++k) {
    const SlabLayer& l = g.layers[k];
    tau[k] = l.optical_thickness();
    if (l.phase == SlabPhase::kLambertSphere) {
      li[k] = 1 / mi;
      lo[k] = 1 / mo;
      reduced[k] = l.albedo[c] * lambert_sphere::phase_function(dot(-wi, wo));
    } else {
      const sggx::Layer m = model_layer(l, c);
      li[k] = m.sigma(wi) / mi;
      lo[k] = m.sigma(wo) / mo;
      reduced[k] = m.reduced_phase(wi, wo);
    }
  }
  double f = 0, above_i = 0, above_o = 0;
  for (std::size_t k = 0; k < n; ++k) {
    double below_o = 0;  // transmission: the layers under k along wo
    for (std::size_t j = k + 1; j < n; ++j) below_o += tau[j] * lo[j];
    const double G = reflection ? sggx::reflection_G(tau[k], li[k], lo[k]) : sggx::transmission_G(tau[k], li[k], lo[k]);
    if (G > 0) f += std::exp(-above_i - (reflection ? above_o : below_o)) * reduced[k] * G / (mi * mo);
    above_i += tau[k] * li[k];
    above_o += tau[k] * lo[k];
  }
  return f;
}


// One path carries all three channels, so channels with the same parameters
// hold the same estimate (identical z): only the first of such channels is
// compared (the others get NaN), or chi2 would count one deviation thrice.
bool distinct_channel(const SlabGeometry& g, int c) {
  auto same = [&](int a, int b) {
    for (const SlabLayer& l : g.layers)
      if (l.albedo[a] != l.albedo[b] || l.f0[a] != l.f0[b]) return false;
    const SlabSubstrate& s = g.substrate;
    switch (s.kind) {
      case SlabSubstrate::Kind::kNone: return true;
      case SlabSubstrate::Kind::kLambertian: return s.albedo[a] == s.albedo[b];
      default: return s.eta[a] == s.eta[b] && s.k[a] == s.k[b];
    }
  };
  for (int b = 0; b < c; ++b)
    if (same(b, c)) return false;
  return true;
}

std::vector<double> drop_duplicate_channels(const SlabGeometry& g, std::vector<double> v) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!distinct_channel(g, static_cast<int>(k % 3))) v[k] = NAN;
  return v;
}

// Cosine-weighted average of f(wi, wo) over every (theta_o, phi) bin, all
// channels: composite Gauss-Legendre in |cos theta_o| and phi (sub x sub
// sub-cells of an n x n rule), since the bins are uniform in |cos theta_o|.
std::vector<double> bin_averages(const Table& t, const std::function<double(int, Vec3, Vec3)>& f) {
  const std::size_t dti = axis_index(t, "theta_i"), dpi = axis_index(t, "phi_i"), dto = axis_index(t, "theta_o"),
                    dph = axis_index(t, "phi"), dch = axis_index(t, "channel");
  const Axis &ti = t.axes[dti], &pi = t.axes[dpi], &to = t.axes[dto], &ph = t.axes[dph];
  static const GaussLegendre rule(8);
  const int sub = 4;
  std::vector<double> out(t.cells(), NAN);
  std::vector<std::size_t> idx(t.axes.size(), 0);
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < pi.size(); ++b) {
      const Vec3 wi = spherical_direction(ti.values[a], pi.values[b]);
      for (std::size_t i = 0; i < to.size(); ++i) {
        const double c0 = std::cos(to.lower(i)), c1 = std::cos(to.upper(i));
        const double mu_lo = std::fmin(std::fabs(c0), std::fabs(c1)), mu_hi = std::fmax(std::fabs(c0), std::fabs(c1));
        const double sign = c0 + c1 >= 0 ? 1.0 : -1.0;
        for (std::size_t j = 0; j < ph.size(); ++j) {
          double num[3] = {0, 0, 0}, den = 0;
          for (int su = 0; su < sub; ++su)
            for (int sv = 0; sv < sub; ++sv) {
              const double m0 = mu_lo + (mu_hi - mu_lo) * su / sub, m1 = mu_lo + (mu_hi - mu_lo) * (su + 1) / sub;
              const double p0 = ph.lower(j) + (ph.upper(j) - ph.lower(j)) * sv / sub;
              const double p1 = ph.lower(j) + (ph.upper(j) - ph.lower(j)) * (sv + 1) / sub;
              for (std::size_t x = 0; x < rule.x.size(); ++x)
                for (std::size_t y = 0; y < rule.x.size(); ++y) {
                  const double mu = 0.5 * (m0 + m1) + 0.5 * (m1 - m0) * rule.x[x];
                  const double phi = 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * rule.x[y];
                  const double w = rule.w[x] * rule.w[y] * (m1 - m0) * (p1 - p0) * mu;
                  const double s = std::sqrt(std::fmax(0.0, 1 - mu * mu));
                  const double po = pi.values[b] + phi;
                  const Vec3 wo{s * std::cos(po), s * std::sin(po), sign * mu};
                  for (int c = 0; c < 3; ++c) num[c] += w * f(c, wi, wo);
                  den += w;
                }
            }
          idx[dti] = a;
          idx[dpi] = b;
          idx[dto] = i;
          idx[dph] = j;
          for (int c = 0; c < 3; ++c) {
            idx[dch] = static_cast<std::size_t>(c);
            out[t.index(idx)] = num[c] / den;
          }
        }
      }
    }
  return out;
}

std::vector<double> evaluate_all_channels(const std::string& model, const Table& t, const Experiment& ex) {
  const SlabGeometry& g = ex.slab;
  if (model == "spongecake_ss_brdf" || model == "spongecake_ss_btdf")
    return bin_averages(t, [&](int c, Vec3 wi, Vec3 wo) { return single_scattering(g, c, wi, wo); });
  if (model == "spongecake_ss_substrate") {
    return bin_averages(t, [&](int c, Vec3 wi, Vec3 wo) {
      std::vector<sggx::Layer> stack;
      for (const SlabLayer& l : g.layers) stack.push_back(model_layer(l, c));
      return single_scattering(g, c, wi, wo) + sggx::lambertian_substrate_term(stack, wi, wo, g.substrate.albedo[c]);
    });
  }
  if (model == "chandrasekhar_isotropic") {
    std::map<double, radiative_transfer::IsotropicHalfSpace> hs;
    for (int c = 0; c < 3; ++c) hs.emplace(g.layers[0].albedo[c], radiative_transfer::IsotropicHalfSpace(g.layers[0].albedo[c]));
    return bin_averages(t, [&](int c, Vec3 wi, Vec3 wo) {
      return wo.z > 0 ? hs.at(g.layers[0].albedo[c]).brdf(wi.z, wo.z) : 0.0;
    });
  }
  if (model == "white_furnace") {
    std::vector<double> out(t.cells());
    const std::size_t nphi = t.axes[1].size();
    for (std::size_t k = 0; k < t.cells(); ++k) {
      const std::size_t c = k % 3, b = (k / 3) % nphi, a = k / (3 * nphi);
      const Vec3 wi = spherical_direction(t.axes[0].values[a], t.axes[1].values[b]);
      std::vector<sggx::Layer> stack;
      for (const SlabLayer& l : g.layers) stack.push_back(model_layer(l, static_cast<int>(c)));
      out[k] = 1 - sggx::delta_transmittance(stack, wi);
    }
    return out;
  }
  throw std::invalid_argument("no slab model " + model);
}

// The channel axis is last in every slab table.
std::vector<double> evaluate_slab_model(const std::string& model, const Table& t, const Experiment& ex) {
  return drop_duplicate_channels(ex.slab, evaluate_all_channels(model, t, ex));
}

std::string slab_model_unsupported(const std::string& model, const Experiment& ex) {
  const SlabGeometry& g = ex.slab;
  for (std::size_t k = 0; k < g.layers.size(); ++k)
    if (g.layers[k].varies_laterally)  // exp(-tau) averaged over the tile is not exp(-mean tau)
      return model + " assumes laterally uniform layers; layer " + std::to_string(k) + "'s density_vdb varies laterally";
  if (model == "spongecake_ss_substrate" && g.substrate.kind != SlabSubstrate::Kind::kLambertian)
    return "spongecake_ss_substrate is implemented for Lambertian substrates";
  if (model == "chandrasekhar_isotropic" &&
      (g.layers.size() != 1 || g.layers[0].phase != SlabPhase::kIsotropic || g.substrate.kind != SlabSubstrate::Kind::kNone))
    return "chandrasekhar_isotropic needs one isotropic layer and no substrate";
  return "";
}

}  // namespace

const ModelFamily& slab_models() {
  static const ModelFamily family{slab_model_list(), evaluate_slab_model, nullptr, slab_model_unsupported};
  return family;
}

}  // namespace mcref
