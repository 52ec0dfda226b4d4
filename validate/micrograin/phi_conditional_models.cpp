// Models of the phi_conditional tables (the vNDF paper's Fig. 5): the density of
// phi' given theta' that the sampler's triangle cut must reproduce exactly
// (Eq. 26, bin averages from the CDF of Eq. 22), and the tent it starts from
// (Eq. 28, slope sign corrected: see models/micrograin/vndf_sampler.h), an
// approximation by construction. Both are computed here from
// models/micrograin/visible_ndf.h, not from the sampler's own code.
#include <cmath>

#include "models/micrograin/visible_ndf.h"
#include "validate/model_evaluation.h"

namespace mcref {

namespace mg = micrograin;

namespace {

std::vector<ModelInfo> phi_conditional_model_list() {
  std::vector<ModelInfo> models{
      {"phi_conditional_eq26", "phi_conditional", true,
       "conditional density of phi' given theta' (vNDF paper Eq. 26; bin averages from the CDF of Eq. 22, with "
       "phi_q where the print has phi_i)"},
      {"phi_conditional_tent_eq28", "phi_conditional", false,
       "the tent approximation of Eq. 26 that the triangle cut starts from (Eq. 28-30: height h0 = Eq. 26 at "
       "+-phi_q, unit mass; slope sign corrected)"},
  };
  for (ModelInfo& m : models) m.kind = "micrograin";
  return models;
}

// CDF of the tent of Eq. 28 (Eq. 29-30) over [-phi_q, phi_q].
double tent_cdf(double theta_i, double theta_m, double phi) {
  const double phi_q = mg::visible_azimuth_bound(theta_i, theta_m);
  const double h0 = mg::visible_ndf_conditional_pdf(theta_i, theta_m, phi_q), h1 = 1 / phi_q - h0;
  const double slope = (h0 - h1) / phi_q, x = std::fmin(std::fabs(phi), phi_q);
  const double half = h1 * x + 0.5 * slope * x * x;  // mass between 0 and |phi|
  return phi < 0 ? 0.5 - half : 0.5 + half;
}

std::vector<double> evaluate(const std::string& model, const Table& t, const Experiment&) {
  const std::size_t di = axis_index(t, "theta_i"), dm = axis_index(t, "theta_m"), du = axis_index(t, "phi_over_phi_q");
  std::vector<double> out(t.cells(), NAN);
  for_each_cell(t, [&](std::size_t k, const std::vector<std::size_t>& i) {
    const double ti = t.axes[di].values[i[di]], tm = t.axes[dm].values[i[dm]];
    const double phi_q = mg::visible_azimuth_bound(ti, tm);
    const double lo = t.axes[du].lower(i[du]) * phi_q, hi = t.axes[du].upper(i[du]) * phi_q;
    auto cdf = [&](double phi) {
      return model == "phi_conditional_eq26" ? mg::visible_ndf_conditional_cdf(ti, tm, phi) : tent_cdf(ti, tm, phi);
    };
    out[k] = (cdf(hi) - cdf(lo)) / (hi - lo);
  });
  return out;
}

}  // namespace

const ModelFamily& micrograin_phi_conditional_models() {
  static const ModelFamily family{phi_conditional_model_list(), evaluate};
  return family;
}

}  // namespace mcref
