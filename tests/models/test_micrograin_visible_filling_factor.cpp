// models/micrograin: visible filling factor and layer weight (LRPB23 Eq. 21–24).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"

using namespace mcref;
using namespace mcref::micrograin;

// gamma_beta is the distance from the centre of an ellipse of radii (1, beta) to
// its tangent lines of direction (sin theta, cos theta) (LRPB23 Fig. 8): the
// support function max_t |(cos t, beta sin t) . (cos theta, -sin theta)|.
TEST(MicrograinVisibleFillingFactor, CompressionFactorIsSupportFunction) {
  for (double beta : {0.1, 0.6, 1.0, 2.0})
    for (double th : {0.0, 0.4, 1.0, 1.5}) {
      double best = 0;
      for (int k = 0; k <= 200000; ++k) {
        const double t = kPi * k / 200000;
        best = std::max(best, std::fabs(std::cos(t) * std::cos(th) - beta * std::sin(t) * std::sin(th)));
      }
      EXPECT_NEAR(compression_factor(beta, th), best, 1e-9);
    }
}

TEST(MicrograinVisibleFillingFactor, LimitsAndSpecialCases) {
  for (double tau0 : {0.1, 0.5, 0.9})
    for (double beta : {0.2, 1.0}) {
      EXPECT_NEAR(tau_beta(tau0, beta, 0.0), tau0, 1e-15);
      EXPECT_NEAR(tau_plus(tau0, beta, 0.0), tau0, 1e-15);
      EXPECT_NEAR(tau_plus(tau0, beta, kPi / 2), 1.0, 1e-12);
      // monotone increasing in theta, tau0 <= tau+ <= tau_beta
      double prev = tau0;
      for (double th = 0.05; th < 1.5; th += 0.05) {
        const double tp = tau_plus(tau0, beta, th), tb = tau_beta(tau0, beta, th);
        EXPECT_GE(tp, prev);
        EXPECT_LE(tp, tb + 1e-15);
        prev = tp;
      }
    }
  // beta = 1: tau_1 = 1 - exp(-pi rs^2 rho / cos theta) (LRPB23 Sec. 5.1).
  EXPECT_NEAR(tau_beta(0.4, 1.0, 0.9), 1 - std::pow(0.6, 1 / std::cos(0.9)), 1e-15);
  // beta -> 0 (flat grains): tau_0(theta) = tau0.
  EXPECT_NEAR(tau_beta(0.4, 0.0, 1.2), 0.4, 1e-15);
}

// Direction forms: unit-space angle theta' with 1/cos theta' = gamma_beta/cos theta.
TEST(MicrograinVisibleFillingFactor, DirectionFormsMatchIsotropicAndAxes) {
  const GrainField iso{0.6, 0.45, 0.45};
  for (double th : {0.0, 0.3, 0.9, 1.4})
    for (double phi : {0.0, 0.7, 2.0, 4.5}) {
      const Vec3 d = spherical_direction(th, phi);
      EXPECT_NEAR(tau_beta(iso, d), tau_beta(0.6, 0.45, th), 1e-14);
      EXPECT_NEAR(tau_plus(iso, d), tau_plus(0.6, 0.45, th), 1e-14);
    }
  // Anisotropic: in the x-z plane only beta_x matters, in the y-z plane only beta_y.
  const GrainField an{0.6, 0.3, 1.5};
  for (double th : {0.2, 0.8, 1.3}) {
    EXPECT_NEAR(tau_plus(an, spherical_direction(th, 0.0)), tau_plus(0.6, 0.3, th), 1e-14);
    EXPECT_NEAR(tau_plus(an, spherical_direction(th, kPi)), tau_plus(0.6, 0.3, th), 1e-14);
    EXPECT_NEAR(tau_plus(an, spherical_direction(th, kPi / 2)), tau_plus(0.6, 1.5, th), 1e-14);
    // in between, between the two
    const double mid = tau_plus(an, spherical_direction(th, 0.8));
    EXPECT_GT(mid, tau_plus(0.6, 0.3, th));
    EXPECT_LT(mid, tau_plus(0.6, 1.5, th));
  }
}

TEST(MicrograinLayerWeight, Eq23EqualsEq24AndIsReciprocal) {
  const GrainField fields[] = {{0.5, 0.5, 0.5}, {0.9, 1.0, 1.0}, {0.3, 0.4, 1.2}};
  for (const GrainField& f : fields)
    for (double ti : {0.0, 0.5, 1.2})
      for (double to : {0.1, 0.8, 1.45}) {
        const Vec3 i = spherical_direction(ti, 0.3), o = spherical_direction(to, 2.1);
        const double w = layer_weight(f, i, o);
        EXPECT_NEAR(w, layer_weight(f, o, i), 1e-15);
        EXPECT_NEAR(layer_weight_eq23(f.tau0, tau_plus(f, i), tau_plus(f, o)), w, 1e-14);
        EXPECT_GE(w, f.tau0 - 1e-15);
        EXPECT_LE(w, 1.0);
      }
  const GrainField f{0.5, 0.5, 0.5};
  const Vec3 n{0, 0, 1};
  EXPECT_NEAR(layer_weight(f, n, n), 0.5, 1e-15);
  // w+(n, o) = tau+(o) (LRPB23 Eq. 26 context: 1 - w+(0, theta_o) = 1 - tau+(theta_o)).
  EXPECT_NEAR(layer_weight(f, n, spherical_direction(1.0, 0.0)), tau_plus(0.5, 0.5, 1.0), 1e-15);
}
