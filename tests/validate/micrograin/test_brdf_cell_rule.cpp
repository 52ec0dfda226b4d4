// validate/micrograin/brdf_cell_rule.h: the rule says whether it met its
// tolerance before its split limit, and the error estimate it reached.
// Integrand: a ridge g = exp(-((theta - 0.7) / w)^2) on [0.2, 1.2] x [0, 1]
// (w = 0.15; theta_i = 0 outside the cell, no kinks, no grazing edge), and a
// constant as second component; exact: w sqrt(pi) erf(0.5 / w) and 1.
// Deterministic: no random numbers.
#include <gtest/gtest.h>

#include <cmath>

#include "validate/micrograin/brdf_cell_rule.h"

using namespace mcref;

namespace {

constexpr double kWidth = 0.15, kT0 = 0.2, kT1 = 1.2, kP0 = 0, kP1 = 1;
const double kExact = kWidth * std::sqrt(kPi) * std::erf(0.5 / kWidth);

CellRuleResult<2> ridge(int max_splits) {
  const auto g = [](double theta, double, double* out) {
    const double x = (theta - 0.7) / kWidth;
    out[0] = std::exp(-x * x);
    out[1] = 1;
  };
  CellRuleTolerance tol{0.5e-6, 1e-300};
  tol.max_splits = max_splits;
  return cell_rule<2>(g, 0.0, kT0, kT1, kP0, kP1, tol);
}

// The cell's scale the tolerance is relative to: the initial estimate (one
// piece here, g > 0: the sum of the pieces' |estimates|).
double scale() { return ridge(0).value[0]; }

}  // namespace

TEST(BrdfCellRule, ConvergedWithinTheDefaultSplitLimit) {
  EXPECT_EQ((CellRuleTolerance{0.5e-6, 0}.max_splits), 200);  // the default the micrograin cells use
  const CellRuleResult<2> r = ridge(200);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.rel_error, 0.5e-6);
  EXPECT_NEAR(r.value[0], kExact, 1e-6 * kExact);
  EXPECT_NEAR(r.value[1], (kT1 - kT0) * (kP1 - kP0), 1e-14);
  EXPECT_LE(r.error[0], 0.5e-6 * scale());
  EXPECT_NEAR(r.rel_error, r.error[0] / scale(), 1e-12 * r.rel_error);
}

// A split budget too small for the ridge: not converged, and the error it
// reached (estimate and actual) is above the tolerance, so the flag is needed.
TEST(BrdfCellRule, ReportsWhenItStopsAtTheSplitLimit) {
  for (const int splits : {0, 1, 3}) {
    const CellRuleResult<2> r = ridge(splits);
    EXPECT_FALSE(r.converged) << splits << " splits";
    EXPECT_GT(r.rel_error, 0.5e-6) << splits << " splits";
    EXPECT_TRUE(std::isfinite(r.rel_error)) << splits << " splits";
    EXPECT_GT(r.error[0], 0.5e-6 * kExact) << splits << " splits";
    EXPECT_GT(std::fabs(r.value[0] - kExact), 0.5e-6 * kExact) << splits << " splits: the value met the tolerance";
    // rel_error is on the scale of the tolerance: the error over the cell's scale.
    EXPECT_NEAR(r.rel_error, r.error[0] / scale(), 1e-12 * r.rel_error) << splits << " splits";
  }
}
