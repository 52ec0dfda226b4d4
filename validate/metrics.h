#pragma once
// Comparison of a simulated table with a model on the same cells.
#include <cstddef>
#include <string>
#include <vector>

namespace mcref {

// Batches from which a cell equal in every batch (stderr 0) is taken as exact:
// B independent batches of a count-like estimate tie on a non-zero value by
// chance with probability at most e^-(B-1) (a Poisson count's largest
// non-zero probability is 1/e), 3e-7 at 16. With fewer (2 batches tie often
// on small counts), such a cell is noted, not judged.
constexpr long long kTieBatches = 16;

struct Comparison {
  std::size_t cells = 0;         // cells compared (finite sim, model and stderr > 0)
  double chi2 = 0;               // sum of z^2
  // Chi-squared survival of each channel's sum of z^2 (its cells as dof), the
  // smallest Bonferroni-corrected over the channels compared; one channel: of chi2.
  double p_value = 1;
  std::size_t channels = 0;      // channels with compared cells
  double max_abs_z = 0;
  std::size_t worst_cell = 0;    // flat index of max |z|
  double max_rel_error = 0;      // max |model - sim| / |sim| over cells with |sim| > 5 se
  double rms_rel_error = 0;
  std::size_t signal_cells = 0;  // cells with |sim| > 5 stderr
  std::size_t exact_cells = 0;   // zero-variance cells where sim equals the model (to 1e-6 relative)
  std::size_t mismatched_exact_cells = 0;  // zero-variance cells that differ slightly, or empty bins
  std::size_t gross_mismatches = 0;  // non-empty zero-variance cells more than 1 % off the model (kTieBatches)
  std::size_t empty_cells = 0;       // cells the simulation left empty (NaN: a batch had no sample)
  std::size_t model_undefined = 0;   // cells with a simulated value where the model is NaN
  // Simulation and model both identically zero: every cell has sim = 0 with
  // stderr 0, and model = 0 (or NaN: not evaluated), at least one cell both 0.
  // Such a check cannot fail (e.g. an all-zero delta table against a model
  // without a delta lobe): judged "n/a".
  bool identically_zero = false;
  // How p_value was found: "sign-flip" (validate/sign_flip.h), "Box" (the chi2
  // against Box's approximation, validate/cell_correlation.h) or "independent"
  // (the chi2 with the cells taken as independent: no batch values).
  std::string joint_test = "independent";
  double smallest_p = 0;  // the smallest p_value the test can give (sign-flip), else 0
  // Box's p where the sign-flip test gave p_value: judge() uses it at a
  // significance below smallest_p (fewer patterns than the level needs).
  double box_p_value = 1;
  // Independent cells' worth, summed over channels: each channel's cells^2 /
  // tr(R^2), R the cells' correlation estimated from the batch values, else
  // its cell count.
  double effective_dof = 0;
  std::vector<double> z;         // per cell (NaN where not compared)
  double chi2_per_dof() const { return cells ? chi2 / static_cast<double>(cells) : 0; }
};

// Per-cell z: the t statistic (sim - model)/stderr with `batches - 1`
// degrees of freedom (the stderr comes from the batch-to-batch spread),
// mapped to the standard normal quantile of the same probability, so that
// chi2 and the |z| bound are exact for any batch count. `model_se` (optional,
// per cell): the standard error of a model that is itself a Monte Carlo
// estimate; it is added in quadrature where the simulation has an error bar,
// with Welch-Satterthwaite degrees of freedom (the model's own count taken as
// infinite). Zero-variance cells are judged as without it.
// `channels` > 1: the last axis holds that many colour channels (cell i is
// channel i % channels). They are estimated from the same paths, so their z
// are correlated (identical for a material whose channels differ only by a
// factor, e.g. Lambertian grains at order 1); a chi2 over all of them would
// count one deviation up to `channels` times. p_value then tests each channel
// by its own chi2 and takes the smallest p times the channel count
// (Bonferroni: valid whatever the correlation; issue #15).
// `batch_values` (optional: batches x cells, Table::batch_values): the cells
// share batches and are correlated, so each channel's p comes from the batches
// themselves: with kMinFlipBatches to kMaxFlipBatches batches and a model
// without noise of its own, the sign-flip test (validate/sign_flip.h, exact
// whatever the correlation); otherwise, from 3 batches, the chi2 against Box's
// approximation c chi2(nu), the correlation estimated from the batches
// (validate/cell_correlation.h). Without batch values the cells are taken as
// independent (c = 1, nu = cells).
Comparison compare(const std::vector<double>& sim, const std::vector<double>& stderr_,
                   const std::vector<double>& model, long long batches, const std::vector<double>& model_se = {},
                   std::size_t channels = 1, const std::vector<double>& batch_values = {});

struct Verdict {
  std::string status;  // "pass", "FAIL", "measured" (approximate model, no tolerance)
                       // or "n/a" (simulation and model identically zero)
  std::string reason;
};

// Identically zero simulation and model: "n/a", whatever the model.
// Exact model: passes iff p_value >= alpha, max|z| <= Sidak bound at alpha,
// and no non-empty zero-variance cell is more than 1 % off.
// Approximate model: passes iff max_rel_error <= tolerance (if tolerance > 0),
// which needs at least one cell with |sim| > 5 stderr.
Verdict judge(const Comparison& c, bool exact, double alpha, double tolerance);

// After judge(): where the sign-flip test cannot give p below alpha (too few
// batches for that level), judge() used Box's p; this makes p_value and
// joint_test say so ("Box"), for what results.json and Python report.
void settle_joint_test(Comparison& c, double alpha);

}  // namespace mcref
