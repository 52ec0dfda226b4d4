// models/micrograin: Smith Lambda three ways (LRPB23 Sec. 5.2, Eq. 25).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "models/core/quadrature.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/smith_lambda.h"
#include "models/micrograin/unit_space.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {
// Independent brute-force Smith integral: 1 + Lambda = ∫ <w.m>+ D(m) dm / cos theta
// over real (theta_m, phi) with both integrals numerical; theta_m split at the
// kink pi/2 - theta, phi split at the zero of w.m.
double lambda_brute_force(double tau0, double beta, double theta) {
  const double sw = std::sin(theta), cw = std::cos(theta);
  auto ring = [&](double tm) {  // ∫ <w.m>+ dphi, numerically
    const double a = sw * std::sin(tm), b = cw * std::cos(tm);
    const double phi0 = (b >= a) ? kPi : std::acos(-b / a);
    return 2 * integrate_composite([&](double p) { return a * std::cos(p) + b; }, 0.0, phi0, 2, 16);
  };
  auto integrand = [&](double tm) { return ndf(tau0, beta, tm) * std::sin(tm) * ring(tm); };
  const double k = kPi / 2 - theta;
  // peak at ~atan(beta): resolve it with many panels
  const double total = integrate_composite(integrand, 0.0, k, 400, 16) +
                       integrate_composite(integrand, k, kPi / 2, 400, 16);
  return total / cw - 1;
}
}  // namespace

// README check: F0..F8 (the general closed form; issue #15) agree with the quadrature of their defining integrals to
// 1e-6 at tau0 = 0.5, beta = 0.8, theta <= 60° (they in fact agree to ~1e-13
// at every angle; checked up to 89°).
TEST(MicrograinSmith, ClosedFormTermsMatchQuadrature) {
  for (double th_deg : {5.0, 15.0, 30.0, 45.0, 60.0})
    for (int k = 0; k <= 4; ++k) {
      const double th = deg_to_rad(th_deg);
      EXPECT_NEAR(lambda_series_term(0.5, 0.8, th, k), lambda_series_term_quadrature(0.5, 0.8, th, k), 1e-6);
    }
  for (double tau0 : {0.2, 0.98})
    for (double beta : {0.3, 1.0, 1.8})
      for (double th_deg : {10.0, 45.0, 75.0, 89.0})
        for (int k = 0; k <= 8; ++k) {
          const double th = deg_to_rad(th_deg);
          const double q = lambda_series_term_quadrature(tau0, beta, th, k);
          EXPECT_NEAR(lambda_series_term(tau0, beta, th, k), q, 1e-11 * std::fmax(1.0, q))
              << tau0 << " " << beta << " " << th_deg << " " << k;
        }
}

// README check: tau0 = 0.98, beta = 1, theta = 80°: truncated series 0.630,
// quadrature 0.686; and the sum of F0..F4 equals the quadrature to 1e-6 at
// tau0 = 0.5, beta = 0.8, theta <= 60°.
TEST(MicrograinSmith, ReadmeNumbers) {
  const GrainField dense{0.98, 1.0, 1.0};
  const double th = deg_to_rad(80);
  EXPECT_NEAR(lambda_series(dense, th, 4), 0.630, 5e-4);
  EXPECT_NEAR(lambda_quadrature(dense, th), 0.686, 5e-4);
  const GrainField f{0.5, 0.8, 0.8};
  for (double th_deg : {10.0, 30.0, 45.0, 60.0}) {
    const double t = deg_to_rad(th_deg);
    EXPECT_NEAR(lambda_series(f, t, 4), lambda_quadrature(f, t), 1e-6) << th_deg;
  }
}

// Issue #15's figures: tau0 = 0.98, beta = 2, theta = 89°: Eq. 25 cut after F4
// gives 19.03, after F6 21.12, the quadrature 21.64. Each added term is
// positive (the series increases toward the quadrature).
TEST(MicrograinSmith, TruncationAtSixTermsIssue15) {
  const GrainField f{0.98, 2.0, 2.0};
  const double th = deg_to_rad(89);
  EXPECT_NEAR(lambda_series(f, th, 4), 19.03, 5e-3);
  EXPECT_NEAR(lambda_series(f, th, 6), 21.12, 5e-3);
  EXPECT_NEAR(lambda_quadrature(f, th), 21.64, 5e-3);
  for (int n = 1; n <= 12; ++n) EXPECT_GT(lambda_series(f, th, n), lambda_series(f, th, n - 1));
}

// The series converges to the Smith integral (n = 40 terms).
TEST(MicrograinSmith, LongSeriesEqualsQuadrature) {
  for (double tau0 : {0.3, 0.9, 0.98})
    for (double beta : {0.4, 1.0})
      for (double th_deg : {20.0, 60.0, 80.0, 89.0}) {
        const GrainField f{tau0, beta, beta};
        const double th = deg_to_rad(th_deg);
        const double q = lambda_quadrature(f, th);
        EXPECT_NEAR(lambda_series(f, th, 40), q, 1e-10 * std::fmax(1.0, q)) << tau0 << " " << beta << " " << th_deg;
      }
}

// Accuracy of the quadrature (b): (1) in the tau0 -> 0 limit it must give the
// closed-form GGX Lambda at alpha = beta, up to 89°; the NDF differs from GGX
// by O(tau0) = 1e-12 there, so this checks the integrator to ~1e-10.
TEST(MicrograinSmith, QuadratureMatchesGgxLimitUpTo89Degrees) {
  for (double beta : {0.1, 0.5, 1.0, 2.0})
    for (double th_deg : {1.0, 30.0, 60.0, 80.0, 85.0, 89.0}) {
      const double th = deg_to_rad(th_deg);
      const double g = ggx_lambda(beta, th);
      EXPECT_NEAR(lambda_quadrature(GrainField{1e-12, beta, beta}, th), g, 1e-9 * g + 1e-15)
          << beta << " " << th_deg;
    }
}

// (2) against an independent brute-force 2-D quadrature of 1 + Lambda (<w.m>+ form).
TEST(MicrograinSmith, QuadratureMatchesBruteForce) {
  for (double tau0 : {0.5, 0.98})
    for (double beta : {0.3, 1.0})
      for (double th_deg : {30.0, 70.0, 89.0}) {
        const double th = deg_to_rad(th_deg);
        const double q = lambda_quadrature(GrainField{tau0, beta, beta}, th);
        EXPECT_NEAR(q, lambda_brute_force(tau0, beta, th), 1e-7 * std::fmax(1.0, q))
            << tau0 << " " << beta << " " << th_deg;
      }
}

// Lambda is invariant under the unit-space map: beta = 1 quadrature at theta'.
TEST(MicrograinSmith, DirectionFormUsesUnitSpace) {
  const GrainField iso{0.7, 0.4, 0.4};
  for (double th : {0.3, 1.0, 1.45})
    for (double phi : {0.0, 2.2}) {
      const double q = lambda_quadrature(iso, th);
      EXPECT_NEAR(lambda_quadrature(iso, spherical_direction(th, phi)), q, 1e-10 * std::fmax(1.0, q));
    }
  const GrainField an{0.7, 0.4, 1.3};
  for (double th : {0.3, 1.0, 1.45}) {
    EXPECT_NEAR(lambda_quadrature(an, spherical_direction(th, 0.0)), lambda_quadrature(GrainField{0.7, 0.4, 0.4}, th), 1e-10);
    EXPECT_NEAR(lambda_quadrature(an, spherical_direction(th, kPi / 2)), lambda_quadrature(GrainField{0.7, 1.3, 1.3}, th), 1e-10);
  }
}

TEST(MicrograinSmith, SeriesLimitsAndGgxAlternative) {
  // tau0 -> 0: F0 / (e^{pi gamma} - 1) -> GGX Lambda at alpha = beta.
  for (double th : {0.2, 0.8, 1.4}) {
    EXPECT_NEAR(lambda_series(GrainField{1e-10, 0.6, 0.6}, th, 0), ggx_lambda(0.6, th), 1e-8 * ggx_lambda(0.6, th));
    EXPECT_EQ(lambda_series(GrainField{0.5, 0.6, 0.6}, 0.0, 4), 0.0);
  }
  EXPECT_EQ(lambda_quadrature(GrainField{0.5, 0.6, 0.6}, 0.0), 0.0);
  // (c): GGX at alpha~ (Eq. 18).
  const GrainField f{0.98, 0.5, 0.5};
  EXPECT_NEAR(lambda_ggx_equivalent(f, 1.0), ggx_lambda(equivalent_roughness(0.98, 0.5), 1.0), 1e-15);
  // LRPB23 Fig. 10: the GGX G1 at alpha~ is conservative (Lambda larger) at tau0 = 0.98.
  for (double th_deg : {40.0, 60.0, 80.0}) {
    const double th = deg_to_rad(th_deg);
    EXPECT_GT(lambda_ggx_equivalent(f, th), lambda_quadrature(f, th));
  }
  // Lambda increases with theta
  double prev = 0;
  for (double th = 0.1; th < 1.55; th += 0.1) {
    const double l = lambda_quadrature(f, th);
    EXPECT_GT(l, prev);
    prev = l;
  }
}
