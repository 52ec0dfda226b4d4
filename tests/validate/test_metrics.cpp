// validate/metrics: the verdicts on constructed comparisons (deterministic).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "models/core/fp_mode.h"
#include "models/core/rng.h"
#include "models/core/statistics.h"
#include "models/core/vec.h"
#include "validate/metrics.h"

using namespace mcref;

// A model that is itself a Monte Carlo estimate (standard error 2x the
// simulation's): ignoring its noise inflates chi2/dof to ~5 and fails an exact
// check; adding it in quadrature gives chi2 ~ chi2(4000). Seed 11, 4000 cells,
// normal noise (batches 10^7: the t map is the identity), alpha = 1e-3.
TEST(Metrics, ModelNoiseEntersInQuadrature) {
  Rng rng(11);
  auto normal = [&] { return std::sqrt(-2 * std::log1p(-rng.uniform())) * std::cos(2 * kPi * rng.uniform()); };
  const std::size_t n = 4000;
  std::vector<double> sim(n), se(n, 0.01), model(n), model_se(n, 0.02);
  for (std::size_t i = 0; i < n; ++i) {
    sim[i] = 1 + se[i] * normal();
    model[i] = 1 + model_se[i] * normal();
  }
  const Comparison without = compare(sim, se, model, 10000000);
  EXPECT_GT(without.chi2_per_dof(), 4.0);
  EXPECT_EQ(judge(without, true, 1e-3, 0).status, "FAIL");
  const Comparison with = compare(sim, se, model, 10000000, model_se);
  EXPECT_EQ(with.cells, n);
  EXPECT_EQ(judge(with, true, 1e-3, 0).status, "pass") << with.chi2_per_dof() << " " << with.max_abs_z;
}

// Welch-Satterthwaite: se = mse = 0.1 with 5 batches gives 16 degrees of
// freedom for t = 1/sqrt(0.02). A zero-variance cell (no error bar from the
// simulation) is judged as without model noise: an equal cell agrees.
TEST(Metrics, ModelNoiseDegreesOfFreedom) {
  const Comparison a = compare({1.0}, {0.1}, {0.0}, 5, {0.1});
  const Comparison b = compare({1.0}, {std::sqrt(0.02)}, {0.0}, 17);  // t with 16 dof, no model noise
  EXPECT_NEAR(a.z[0], b.z[0], 1e-12);
  const Comparison c = compare({0.7}, {0.0}, {0.7}, 5, {1e-17});
  EXPECT_EQ(c.cells, 0u);
  EXPECT_EQ(c.exact_cells, 1u);
}

TEST(Metrics, ExactModelWithinErrorPasses) {
  const std::vector<double> sim{1.0, 2.0, 3.0}, se{0.1, 0.1, 0.1}, model{1.05, 1.95, 3.0};
  const Comparison c = compare(sim, se, model, 32);
  EXPECT_EQ(c.cells, 3u);
  EXPECT_EQ(judge(c, true, 1e-3, 0).status, "pass");
}

TEST(Metrics, ExactModelFarOffFails) {
  const std::vector<double> sim{1.0, 2.0, 3.0}, se{0.01, 0.01, 0.01}, model{1.0, 2.0, 3.2};
  EXPECT_EQ(judge(compare(sim, se, model, 32), true, 1e-3, 0).status, "FAIL");
}

// A cell equal in every batch (stderr 0) far from an exact model fails even
// beside cells with error bars; an empty bin (sim 0) is only noted.
TEST(Metrics, GrossZeroVarianceMismatchFailsExactModels) {
  const std::vector<double> se{0.1, 0.0}, model{1.0, 0.9};
  EXPECT_EQ(judge(compare({1.0, 1.0}, se, model, 32), true, 1e-3, 0).status, "FAIL");
  EXPECT_EQ(judge(compare({1.0, 0.0}, se, model, 32), true, 1e-3, 0).status, "pass");
  EXPECT_EQ(judge(compare({1.0, 0.9}, se, model, 32), true, 1e-3, 0).status, "pass");
  // Two batches that tie by chance (small counts: 0.688 in both, the model
  // 0.634) are no evidence: noted, not failed, below kTieBatches batches.
  const Comparison two = compare({1.0, 0.688}, se, {1.0, 0.634}, 2);
  EXPECT_EQ(two.gross_mismatches, 0u);
  EXPECT_EQ(two.mismatched_exact_cells, 1u);
  EXPECT_EQ(judge(two, true, 1e-3, 0).status, "pass");
  EXPECT_EQ(judge(compare({1.0, 0.688}, se, {1.0, 0.634}, kTieBatches), true, 1e-3, 0).status, "FAIL");
}

TEST(Metrics, ToleranceNeedsSignal) {
  // |sim| < 5 stderr everywhere: the tolerance cannot be checked.
  const std::vector<double> sim{0.1, 0.2}, se{0.1, 0.1}, model{0.0, 0.0};
  EXPECT_EQ(judge(compare(sim, se, model, 32), false, 1e-3, 0.05).status, "FAIL");
  // With signal, a model of 0 counts as 100 % off.
  const Comparison c = compare({1.0}, {0.01}, {0.0}, 32);
  EXPECT_DOUBLE_EQ(c.max_rel_error, 1.0);
  EXPECT_EQ(judge(c, false, 1e-3, 0.05).status, "FAIL");
}

// The relative error is the model's, against the simulation (the reference):
// a model at half the simulation is 50 % off, one at twice it 100 % off; the
// cell below 5 stderr is left out. The plots' residual uses the same cells.
TEST(Metrics, RelativeErrorIsAgainstTheSimulation) {
  const Comparison c = compare({2.0, 2.0, 0.04}, {0.01, 0.01, 0.01}, {1.0, 4.0, 1.0}, 32);
  EXPECT_EQ(c.signal_cells, 2u);
  EXPECT_DOUBLE_EQ(c.max_rel_error, 1.0);
  EXPECT_DOUBLE_EQ(c.rms_rel_error, std::sqrt((0.25 + 1.0) / 2));
}

// The t -> z map: with 1 batch of freedom more the z shrinks toward the normal.
TEST(Metrics, StudentTailsAreMappedToNormalQuantiles) {
  const Comparison few = compare({3.0}, {1.0}, {0.0}, 4), many = compare({3.0}, {1.0}, {0.0}, 10000);
  EXPECT_LT(few.max_abs_z, many.max_abs_z);
  EXPECT_NEAR(many.max_abs_z, 3.0, 1e-2);
}

// Embree's threads may run with flush-to-zero / denormals-are-zero. Results
// that underflow below the normal range must not depend on that mode, or a
// check's p-value (and the z of extreme cells) would depend on which thread
// computed it: 144 normal cells at z = 3.7 (p ~ 1e-316, a denormal), and
// Student cells (16 batches) whose tails reach and pass the denormal range.
TEST(Metrics, UnderflowDoesNotDependOnFlushToZero) {
#ifndef MCREF_HAS_MXCSR
  GTEST_SKIP() << "MXCSR flush-to-zero is an x86 mode";
#else
  const std::vector<double> se(144, 1.0), model(144, 1.0);
  std::vector<double> normal_cells(144, 1.0 + 3.7), student_cells(144, 1.0);
  for (std::size_t i = 0; i < student_cells.size(); ++i) student_cells[i] += std::pow(10.0, 0.25 * i);  // t = 1 .. 1e36
  const unsigned saved = _mm_getcsr();
  const Comparison a = compare(normal_cells, se, model, 100000000), b = compare(student_cells, se, model, 16);
  _mm_setcsr(saved | IeeeDenormals::kFlushBits);  // FTZ | DAZ
  const Comparison a_ftz = compare(normal_cells, se, model, 100000000), b_ftz = compare(student_cells, se, model, 16);
  _mm_setcsr(saved);
  EXPECT_EQ(a.p_value, a_ftz.p_value);
  EXPECT_GT(a.p_value, 0.0);  // gradual underflow: a denormal, not 0
  EXPECT_LT(a.p_value, std::numeric_limits<double>::min());
  for (std::size_t i = 0; i < student_cells.size(); ++i) EXPECT_EQ(b.z[i], b_ftz.z[i]) << "cell " << i;
  EXPECT_EQ(b.chi2, b_ftz.chi2);
#endif
}

// Empty cells (NaN value and NaN stderr: a batch had no sample) are left out
// of the comparison and counted in the note; a NaN sum gives a NaN stderr, not 0.
TEST(Metrics, EmptyCellsAreCountedNotCompared) {
  EXPECT_TRUE(std::isnan(stderr_of_mean(NAN, NAN, 3)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Comparison c = compare({1.0, nan, 3.0}, {0.1, nan, 0.1}, {1.0, 2.0, 3.0}, 32);
  EXPECT_EQ(c.cells, 2u);
  EXPECT_EQ(c.empty_cells, 1u);
  const Verdict v = judge(c, true, 1e-3, 0);
  EXPECT_EQ(v.status, "pass");
  EXPECT_NE(v.reason.find("1 empty cells"), std::string::npos) << v.reason;
  const Verdict none = judge(compare({nan}, {nan}, {1.0}, 32), true, 1e-3, 0);
  EXPECT_NE(none.reason.find("1 empty cells"), std::string::npos) << none.reason;
}

// "n/a": a simulation and a model both identically zero (an all-zero delta
// table against a model without a delta lobe) cannot fail; it is neither a
// pass nor a failure. Cells where the model is NaN (not evaluated, e.g. a
// duplicate channel) do not count; any non-zero value on either side does.
TEST(Metrics, IdenticallyZeroIsNotApplicable) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> zeros(4, 0.0);
  for (bool exact : {true, false}) {
    const Comparison c = compare(zeros, zeros, zeros, 32);
    EXPECT_TRUE(c.identically_zero);
    EXPECT_EQ(judge(c, exact, 1e-3, 0).status, "n/a");
    EXPECT_EQ(judge(c, exact, 1e-3, 0.05).status, "n/a");
    EXPECT_EQ(judge(compare(zeros, zeros, {0.0, nan, 0.0, nan}, 32), exact, 1e-3, 0).status, "n/a");
  }
  // Either side non-zero in one cell: an ordinary check.
  const Comparison sim_nonzero = compare({0.0, 0.0, 1e-9, 0.0}, zeros, zeros, 32);
  EXPECT_FALSE(sim_nonzero.identically_zero);
  EXPECT_NE(judge(sim_nonzero, true, 1e-3, 0).status, "n/a");
  const Comparison model_nonzero = compare(zeros, zeros, {0.0, 0.0, 0.0, 0.5}, 32);
  EXPECT_FALSE(model_nonzero.identically_zero);
  EXPECT_EQ(judge(model_nonzero, true, 1e-3, 0).status, "FAIL");  // a zero-variance cell that differs
  const Comparison model_tiny = compare(zeros, zeros, {0.0, 0.0, 0.0, 1e-12}, 32);
  EXPECT_FALSE(model_tiny.identically_zero);
  EXPECT_EQ(judge(model_tiny, true, 1e-3, 0).status, "pass");  // equal to 1e-6: a check that could have failed
  // Batches that differ (stderr > 0) though the mean is 0: not identically zero.
  const Comparison noisy = compare(zeros, {0.0, 0.1, 0.0, 0.0}, zeros, 32);
  EXPECT_FALSE(noisy.identically_zero);
  EXPECT_EQ(judge(noisy, true, 1e-3, 0).status, "pass");
  // No model value at all: not n/a either.
  EXPECT_EQ(judge(compare(zeros, zeros, std::vector<double>(4, nan), 32), true, 1e-3, 0).status, "FAIL");
  // Zeros on both sides beside an empty cell (NaN: a batch had no sample): still
  // nothing to check, so n/a, naming the empty cell (it was a "pass" on 0 vs 0).
  const Comparison with_empty = compare({0.0, nan, 0.0, 0.0}, {0.0, nan, 0.0, 0.0}, zeros, 32);
  EXPECT_TRUE(with_empty.identically_zero);
  const Verdict v = judge(with_empty, true, 1e-3, 0);
  EXPECT_EQ(v.status, "n/a");
  EXPECT_NE(v.reason.find("1 empty cells"), std::string::npos) << v.reason;
  // An empty cell where the model is not zero: an ordinary check (not n/a).
  EXPECT_FALSE(compare({0.0, nan, 0.0, 0.0}, {0.0, nan, 0.0, 0.0}, {0.0, 0.5, 0.0, 0.0}, 32).identically_zero);
  EXPECT_FALSE(compare(zeros, zeros, {0.0, 0.0, std::numeric_limits<double>::infinity(), 0.0}, 32).identically_zero);
}

// Issue #15: the RGB channels of a table come from the same paths; for
// Lambertian grains at order 1 they differ only by the albedo, so their z are
// identical and a chi2 over all cells counts each deviation three times (its
// variance triples). Seed 5, 2000 replications of an exact model on 200 cells x
// 3 such channels (normal noise, 10^7 batches), alpha = 0.01: one chi2 over the
// 600 cells rejects the true model in about 9 % of the replications (P(3 X > the
// 1 % point of chi2(600)), X ~ chi2(200)); the per-channel chi2 with Bonferroni
// in at most alpha (here alpha / 3: the three p are equal). A 5 % scaled model
// (z ~ -1 per cell with 5 % errors) still fails.
TEST(Metrics, CorrelatedChannelsAreTestedOneByOne) {
  Rng rng(5);
  auto normal = [&] { return std::sqrt(-2 * std::log1p(-rng.uniform())) * std::cos(2 * kPi * rng.uniform()); };
  const double albedo[3] = {0.18, 0.67, 0.42}, alpha = 0.01;
  const std::size_t rows = 200, reps = 2000;
  std::size_t pooled_rejections = 0, channel_rejections = 0;
  std::vector<double> sim(3 * rows), se(3 * rows), model(3 * rows), scaled(3 * rows);
  for (std::size_t r = 0; r < reps; ++r) {
    for (std::size_t k = 0; k < rows; ++k) {
      const double e = normal();
      for (int ch = 0; ch < 3; ++ch) {
        model[3 * k + ch] = albedo[ch];
        scaled[3 * k + ch] = 1.05 * albedo[ch];
        sim[3 * k + ch] = albedo[ch] * (1 + 0.05 * e);
        se[3 * k + ch] = albedo[ch] * 0.05;
      }
    }
    const Comparison pooled = compare(sim, se, model, 10000000), split = compare(sim, se, model, 10000000, {}, 3);
    EXPECT_EQ(split.channels, 3u);
    EXPECT_EQ(split.chi2, pooled.chi2);
    pooled_rejections += pooled.p_value < alpha;
    channel_rejections += split.p_value < alpha;
    if (r == 0) EXPECT_EQ(judge(compare(sim, se, scaled, 10000000, {}, 3), true, alpha, 0).status, "FAIL");
  }
  // Binomial: pooled ~ 9 % +- 0.6 %; split <= 1 % (sd 0.22 % at 1 %).
  EXPECT_GT(pooled_rejections, reps * 6 / 100) << pooled_rejections;
  EXPECT_LE(channel_rejections, reps * 15 / 1000) << channel_rejections;
}

// One channel: the per-channel p is the pooled chi2's p.
TEST(Metrics, SingleChannelPValueIsThePooledOne) {
  const std::vector<double> sim{1.1, 2.0, 2.9}, se{0.1, 0.1, 0.1}, model{1.0, 2.0, 3.0};
  const Comparison c = compare(sim, se, model, 10000000);
  EXPECT_EQ(c.channels, 1u);
  EXPECT_NEAR(c.p_value, chi2_survival(c.chi2, 3), 1e-15);
}
