// validate/metrics: the verdicts on constructed comparisons (deterministic).
#include <gtest/gtest.h>

#include <cmath>

#include "validate/metrics.h"

using namespace mcref;

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
}

TEST(Metrics, ToleranceNeedsSignal) {
  // |sim| < 5 stderr everywhere: the tolerance cannot be checked.
  const std::vector<double> sim{0.1, 0.2}, se{0.1, 0.1}, model{0.0, 0.0};
  EXPECT_EQ(judge(compare(sim, se, model, 32), false, 1e-3, 0.05).status, "FAIL");
  // With signal, a model of 0 counts as 100 % off.
  const Comparison c = compare({1.0}, {0.01}, {0.0}, 32);
  EXPECT_GE(c.max_rel_error, 1.0);
  EXPECT_EQ(judge(c, false, 1e-3, 0.05).status, "FAIL");
}

// The t -> z map: with 1 batch of freedom more the z shrinks toward the normal.
TEST(Metrics, StudentTailsAreMappedToNormalQuantiles) {
  const Comparison few = compare({3.0}, {1.0}, {0.0}, 4), many = compare({3.0}, {1.0}, {0.0}, 10000);
  EXPECT_LT(few.max_abs_z, many.max_abs_z);
  EXPECT_NEAR(many.max_abs_z, 3.0, 1e-2);
}
