// Isotropic and Henyey-Greenstein phase functions: normalisation and mean
// cosine by quadrature (pole at -wi; 32 x 64 panels of 8 x 8 points, error
// < 1e-10 for |g| <= 0.9, tolerance 1e-8), and chi-square goodness of fit of
// the samplers (10^6 samples, 64 x 128 equal-area bins around -wi, level 0.01
// Sidak-corrected over the chi-square tests of this file, fixed seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "models/sggx/hg_phase.h"
#include "tests/models/sggx_chi2.h"
#include "tests/models/sggx_quadrature.h"

namespace {

using mcref::Vec3;
namespace sg = mcref::sggx;
namespace mt = mcref::sggx_test;

const std::vector<double> kG = {-0.7, -0.2, 0.0, 1e-7, 0.3, 0.9};
const Vec3 kWi = mcref::spherical_direction(2.2, 1.0);
// chi-square tests in this file: one per g, plus the isotropic one.
const int kNumChi2Tests = static_cast<int>(kG.size()) + 1;

TEST(sggxHgPhase, NormalisedWithMeanCosineG) {
  for (double g : kG) {
    const double norm = mt::integrate_sphere([&](Vec3 wo) { return sg::hg_phase(g, kWi, wo); }, -kWi, 32, 64);
    const double mean = mt::integrate_sphere([&](Vec3 wo) { return -dot(kWi, wo) * sg::hg_phase(g, kWi, wo); },
                                             -kWi, 32, 64);
    EXPECT_NEAR(norm, 1.0, 1e-8) << g;
    EXPECT_NEAR(mean, g, 1e-8) << g;
  }
  EXPECT_DOUBLE_EQ(sg::hg_phase(0.0, kWi, {0, 0, 1}), sg::isotropic_phase());
}

TEST(sggxHgPhase, ForwardMeansAlongPropagation) {
  // g > 0 peaks at wo = -wi (the photon keeps going), p = (1+g)/(4 pi (1-g)^2).
  const double g = 0.6;
  EXPECT_NEAR(sg::hg_phase(g, kWi, -kWi), (1 + g) / (4 * mcref::kPi * (1 - g) * (1 - g)), 1e-12);
  EXPECT_GT(sg::hg_phase(g, kWi, -kWi), sg::hg_phase(g, kWi, kWi));
}

TEST(sggxHgPhase, CosineInversionIsMonotoneAndExact) {
  for (double g : kG) {
    EXPECT_NEAR(sg::sample_hg_cos_theta(g, 0.0), -1.0, 1e-14);
    EXPECT_NEAR(sg::sample_hg_cos_theta(g, 1.0), 1.0, 1e-14);
    double prev = -2;
    for (int k = 0; k <= 100; ++k) {
      const double c = sg::sample_hg_cos_theta(g, k / 100.0);
      EXPECT_GE(c, prev);
      prev = c;
      if (std::fabs(g) > 1e-3) {  // closed-form CDF at c equals u
        const double cdf = (1 - g * g) / (2 * g) * (1 / std::sqrt(1 + g * g - 2 * g * c) - 1 / (1 + g));
        EXPECT_NEAR(cdf, k / 100.0, 1e-12);
      }
    }
  }
}

class sggxHgChi2 : public ::testing::TestWithParam<std::size_t> {};

TEST_P(sggxHgChi2, MatchesHg) {
  const double g = kG[GetParam()];
  mt::Chi2Options opt;
  opt.seed = 3000 + GetParam();
  opt.pole = -kWi;
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [&](double u1, double u2) {
        const sg::PhaseSample s = sg::sample_hg_phase(g, 0.5, kWi, u1, u2);
        EXPECT_NEAR(s.pdf, sg::hg_phase(g, kWi, s.wo), 1e-9 * s.pdf);
        return s.wo;
      },
      [&](Vec3 wo) { return sg::hg_phase(g, kWi, wo); }, opt);
  EXPECT_EQ(r.bad_samples, 0) << r.message;
  EXPECT_NEAR(r.pdf_mass, 1.0, 1e-6) << r.message;
  EXPECT_GT(r.p_value, mt::sidak_significance(0.01, kNumChi2Tests)) << r.message;
}

INSTANTIATE_TEST_SUITE_P(G, sggxHgChi2, ::testing::Range<std::size_t>(0, kG.size()));

TEST(sggxIsotropicChi2, MatchesUniform) {
  mt::Chi2Options opt;
  opt.seed = 3100;
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [&](double u1, double u2) { return sg::sample_isotropic_phase(1.0, u1, u2).wo; },
      [&](Vec3) { return sg::isotropic_phase(); }, opt);
  EXPECT_GT(r.p_value, mt::sidak_significance(0.01, kNumChi2Tests)) << r.message;
}

}  // namespace
