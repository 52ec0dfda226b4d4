#include "validate/metrics.h"

#include <cmath>
#include <cstdio>

#include "models/core/fp_mode.h"
#include "models/core/statistics.h"
#include "validate/cell_correlation.h"
#include "validate/sign_flip.h"

namespace mcref {

Comparison compare(const std::vector<double>& sim, const std::vector<double>& se, const std::vector<double>& model,
                   long long batches, const std::vector<double>& model_se, std::size_t channels,
                   const std::vector<double>& batch_values) {
  const IeeeDenormals ieee;  // the same z and p-value on every thread (models/core/fp_mode.h)
  Comparison c;
  c.z.assign(sim.size(), NAN);
  const double nu = static_cast<double>(batches - 1);
  double rel2 = 0;
  channels = channels > 0 ? channels : 1;
  std::vector<double> channel_chi2(channels, 0.0);
  std::vector<std::size_t> channel_cells(channels, 0);
  // Each channel's compared cells, and the share of their z variance that is the simulation's.
  std::vector<std::vector<std::size_t>> compared(channels);
  std::vector<std::vector<double>> sim_share(channels);
  std::size_t zero_pairs = 0, nonzero = 0;  // for identically_zero
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (sim[i] == 0 && se[i] == 0 && (model[i] == 0 || std::isnan(model[i]))) zero_pairs += model[i] == 0;
    else if (!std::isnan(sim[i]) || (model[i] != 0 && !std::isnan(model[i]))) ++nonzero;  // an empty cell (NaN) beside zeros: still n/a
    if (!std::isfinite(sim[i]) || !std::isfinite(model[i]) || !std::isfinite(se[i])) {
      if (std::isnan(sim[i])) ++c.empty_cells;
      if (std::isfinite(sim[i]) && !std::isfinite(model[i])) ++c.model_undefined;
      continue;
    }
    if (se[i] <= 0) {
      // Every batch gave the same value (all paths scattered, every sample
      // visible, or a bin that stayed empty): there is no error bar. Equal to
      // 1e-6 counts as agreement; a gross difference (> 1 %) of a non-empty
      // cell as disagreement, when the batches are enough for a tie not to be
      // chance; otherwise, and for an empty bin (sim = 0), it is only noted.
      const double diff = std::fabs(sim[i] - model[i]);
      if (diff <= 1e-6 * std::fmax(1.0, std::fabs(model[i]))) ++c.exact_cells;
      else if (sim[i] != 0 && diff > 1e-2 * std::fabs(model[i]) && batches >= kTieBatches) ++c.gross_mismatches;
      else ++c.mismatched_exact_cells;
      continue;
    }

    // A model with Monte Carlo noise of its own (many samples: normal) adds
    // it in quadrature; the degrees of freedom follow Welch-Satterthwaite.
    const double mse = model_se.empty() || !std::isfinite(model_se[i]) ? 0.0 : model_se[i];
    const double var = se[i] * se[i] + mse * mse, r = var / (se[i] * se[i]);
    const double t = (sim[i] - model[i]) / std::sqrt(var);
    const double nu_eff = nu * r * r;
    // From t(nu) to N(0, 1) preserving probability (beyond double range: t, the verdict is FAIL anyway).
    const double z = t_to_normal(t, nu_eff);
    c.z[i] = z;
    ++c.cells;
    c.chi2 += z * z;
    channel_chi2[i % channels] += z * z;
    ++channel_cells[i % channels];
    compared[i % channels].push_back(i);
    sim_share[i % channels].push_back(1 / std::sqrt(r));
    if (std::fabs(z) > c.max_abs_z) {
      c.max_abs_z = std::fabs(z);
      c.worst_cell = i;
    }
    // The model's error relative to the reference, over cells where the
    // simulation is significant (its own relative noise below 20 %).
    if (std::fabs(sim[i]) > 5 * se[i]) {
      const double rel = std::fabs(model[i] - sim[i]) / std::fabs(sim[i]);
      c.max_rel_error = std::fmax(c.max_rel_error, rel);
      rel2 += rel * rel;
      ++c.signal_cells;
    }
  }
  c.identically_zero = zero_pairs > 0 && nonzero == 0;
  const bool have_batches = batches >= 3 && batch_values.size() == static_cast<std::size_t>(batches) * sim.size();
  bool model_noise = false;
  for (const std::vector<double>& share : sim_share)
    for (double w : share) model_noise = model_noise || w < 1;
  if (have_batches)
    c.joint_test = !model_noise && batches >= kMinFlipBatches && batches <= kMaxFlipBatches ? "sign-flip" : "Box";
  double p_min = 1, box_min = 1;
  for (std::size_t k = 0; k < channels; ++k)
    if (channel_cells[k] > 0) {
      ++c.channels;
      // Box: chi2 ~ scale chi2(dof), scale = tr(R^2) / cells, dof = cells^2 / tr(R^2).
      const double cells = static_cast<double>(channel_cells[k]);
      const double trace =
          have_batches ? correlation_square_trace(batch_values, sim.size(), batches, compared[k], sim_share[k]) : cells;
      const double scale = trace / cells, dof = cells * cells / trace;
      c.effective_dof += dof;
      const double box = chi2_survival(channel_chi2[k] / scale, dof);
      box_min = std::fmin(box_min, box);
      p_min = std::fmin(p_min, c.joint_test == "sign-flip"
                                   ? sign_flip_p_value(batch_values, sim.size(), batches, compared[k], model)
                                   : box);
    }
  const double bonferroni = static_cast<double>(c.channels > 0 ? c.channels : 1);
  if (c.joint_test == "sign-flip") c.smallest_p = std::fmin(1.0, sign_flip_smallest_p(batches) * bonferroni);
  c.p_value = std::fmin(1.0, p_min * bonferroni);
  c.box_p_value = std::fmin(1.0, box_min * bonferroni);
  c.rms_rel_error = c.signal_cells ? std::sqrt(rel2 / c.signal_cells) : 0;
  return c;
}

namespace {

// Whether the sign-flip test has too few patterns for the level alpha: then
// judge() uses Box's approximation instead.
bool flips_too_few(const Comparison& c, double alpha) { return c.joint_test == "sign-flip" && c.smallest_p > alpha; }

// How the joint test was made, for the verdict's reason.
std::string joint_text(const Comparison& c, double alpha) {
  char buf[200];
  if (flips_too_few(c, alpha))
    std::snprintf(buf, sizeof buf,
                  "chi2 with %.3g effective dof from the batches' correlation (Box): the sign-flip test cannot give p "
                  "below %.2g with these batches",
                  c.effective_dof, c.smallest_p);
  else if (c.joint_test == "sign-flip")
    std::snprintf(buf, sizeof buf, "sign-flip test over the batches; %.3g independent cells' worth", c.effective_dof);
  else if (c.joint_test == "Box")
    std::snprintf(buf, sizeof buf, "chi2 with %.3g effective dof from the batches' correlation (Box)", c.effective_dof);
  else
    std::snprintf(buf, sizeof buf, "chi2 with the cells taken as independent: no batch values, or under 3 batches");
  return buf;
}

}  // namespace

void settle_joint_test(Comparison& c, double alpha) {
  if (!flips_too_few(c, alpha)) return;
  c.p_value = c.box_p_value;
  c.joint_test = "Box";
}

Verdict judge(const Comparison& c, bool exact, double alpha, double tolerance) {
  char buf[512];
  if (c.identically_zero) {
    std::snprintf(buf, sizeof buf, "simulation and model are zero in all %zu cells that have a model value: nothing to check",
                  c.exact_cells);
    return {"n/a", buf + (c.empty_cells ? "; " + std::to_string(c.empty_cells) + " empty cells (NaN: a batch had no sample)"
                                        : std::string())};
  }
  if (exact && c.gross_mismatches > 0) {
    std::snprintf(buf, sizeof buf, "%zu zero-variance cells differ from the model by more than 1 %%", c.gross_mismatches);
    return {"FAIL", buf};
  }
  if (c.cells == 0) {
    // Only zero-variance cells: they decide alone.
    if (c.exact_cells > 0 && c.mismatched_exact_cells == 0) {
      std::snprintf(buf, sizeof buf, "all %zu cells have zero variance and equal the model", c.exact_cells);
      return {"pass", buf};
    }
    if (c.mismatched_exact_cells + c.gross_mismatches > 0) {
      std::snprintf(buf, sizeof buf, "%zu zero-variance cells differ from the model",
                    c.mismatched_exact_cells + c.gross_mismatches);
      return {exact ? "FAIL" : "measured", buf};
    }
    return {"FAIL", "no cell could be compared" +
                        (c.empty_cells ? " (" + std::to_string(c.empty_cells) + " empty cells: a batch had no sample)" : std::string())};
  }
  // Zero-variance cells beside cells with error bars (e.g. a rare cell that
  // stayed empty in every batch) carry no error bar to judge by: noted only.
  std::string note;
  if (c.mismatched_exact_cells > 0)
    note = "; " + std::to_string(c.mismatched_exact_cells) + " zero-variance cells differ slightly or are empty (not judged)";
  if (c.empty_cells > 0) note += "; " + std::to_string(c.empty_cells) + " empty cells (NaN: a batch had no sample) not compared";
  if (c.model_undefined > 0) note += "; model undefined on " + std::to_string(c.model_undefined) + " cells";
  if (exact) {
    const double bound = sidak_z_bound(alpha, static_cast<double>(c.cells));
    const double p = flips_too_few(c, alpha) ? c.box_p_value : c.p_value;
    if (p < alpha) {
      // Say how the chi2's dof were set, and whether the |z| bound (valid whatever the
      // correlation) agrees.
      std::snprintf(buf, sizeof buf, "chi2/dof = %.3g over %zu cells (%s), p = %.2g < %.2g%s; max |z| = %.2f %s %.2f",
                    c.chi2_per_dof(), c.cells, joint_text(c, alpha).c_str(), p, alpha,
                    c.channels > 1 ? " (worst channel's p, Bonferroni over channels)" : "", c.max_abs_z,
                    c.max_abs_z > bound ? ">" : "<=", bound);
      return {"FAIL", buf + note};
    }
    if (c.max_abs_z > bound) {
      std::snprintf(buf, sizeof buf, "max |z| = %.2f > %.2f (Sidak bound at %.2g over %zu cells)", c.max_abs_z, bound,
                    alpha, c.cells);
      return {"FAIL", buf + note};
    }
    std::snprintf(buf, sizeof buf, "p = %.2g >= %.2g (%s); max |z| = %.2f <= %.2f", p, alpha, joint_text(c, alpha).c_str(),
                  c.max_abs_z, bound);
    return {"pass", buf + note};
  }
  if (tolerance > 0 && c.signal_cells == 0) return {"FAIL", "no cell has enough signal (|sim| > 5 stderr) to check the tolerance" + note};
  if (tolerance > 0) {
    std::snprintf(buf, sizeof buf, "max rel. error %.3g %s tolerance %.3g", c.max_rel_error,
                  c.max_rel_error <= tolerance ? "<=" : ">", tolerance);
    return {c.max_rel_error <= tolerance ? "pass" : "FAIL", buf + note};
  }
  std::snprintf(buf, sizeof buf, "max rel. error %.3g, rms %.3g (approximate model, no tolerance set)",
                c.max_rel_error, c.rms_rel_error);
  return {"measured", buf + note};
}

}  // namespace mcref
