// Checks of the chi-square helper itself (tests/models/sggx_chi2.h): the
// regularised incomplete gamma against closed forms, and the test's power on
// a deliberately wrong pdf (negative control).
#include <gtest/gtest.h>

#include <cmath>

#include "models/core/warp.h"
#include "models/sggx/sggx_distribution.h"
#include "tests/models/sggx_chi2.h"

namespace {

namespace mt = mcref::sggx_test;
namespace sg = mcref::sggx;

TEST(sggxChi2Helper, IncompleteGammaClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    // Q(1, x) = e^-x; Q(1/2, x) = erfc(sqrt x); Q(2, x) = (1 + x) e^-x.
    EXPECT_NEAR(mt::regularized_gamma_q(1.0, x), std::exp(-x), 1e-14);
    EXPECT_NEAR(mt::regularized_gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-14);
    EXPECT_NEAR(mt::regularized_gamma_q(2.0, x), (1 + x) * std::exp(-x), 1e-14);
  }
  // Large dof: the chi-square median is close to dof (1 - 2/(9 dof))^3.
  for (double k : {100.0, 4000.0}) {
    const double median = k * std::pow(1 - 2 / (9 * k), 3);
    EXPECT_NEAR(mt::chi2_survival(median, k), 0.5, 2e-3);
  }
  EXPECT_NEAR(mt::sidak_significance(0.01, 1), 0.01, 1e-15);
  EXPECT_NEAR(mt::sidak_significance(0.01, 36), 1 - std::pow(0.99, 1.0 / 36), 1e-15);
}

TEST(sggxChi2Helper, UniformSphereSamplerPasses) {
  mt::Chi2Options opt;
  opt.seed = 5;
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [](double u1, double u2) { return mcref::sample_uniform_sphere(u1, u2); },
      [](mcref::Vec3) { return 1 / (4 * mcref::kPi); }, opt);
  EXPECT_NEAR(r.pdf_mass, 1.0, 1e-12);
  EXPECT_GT(r.p_value, mt::sidak_significance(0.01, 1)) << r.message;  // the only pass test here
}

TEST(sggxChi2Helper, DetectsAWrongPdf) {
  // vNDF samples at alpha = 0.5 tested against the vNDF at alpha = 0.55.
  const sg::Sggx s = sg::surface_like(0.5, {0, 0, 1}), wrong = sg::surface_like(0.55, {0, 0, 1});
  const mcref::Vec3 w = mcref::spherical_direction(1.0, 0.0);
  mt::Chi2Options opt;
  opt.seed = 6;
  opt.pole = w;
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [&](double u1, double u2) { return sg::sample_visible_normal(s, w, u1, u2); },
      [&](mcref::Vec3 m) { return sg::visible_ndf(wrong, w, m); }, opt);
  EXPECT_LT(r.p_value, 1e-6) << r.message;
}

}  // namespace
