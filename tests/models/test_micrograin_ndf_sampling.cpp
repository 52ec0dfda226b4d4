// models/micrograin: NDF sampling (LRPB23 Eq. 19–20) and the chi-square helper.
#include <gtest/gtest.h>

#include <cmath>

#include "chi2.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/ndf_sampling.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {
// Chi-square tests in this file (Šidák correction at family-wise alpha = 0.01).
constexpr int kChi2Tests = 5;
const double kAlpha = test::sidak_alpha(0.01, kChi2Tests);
constexpr std::uint64_t kSamples = 1000000;

void run_chi2(const GrainField& f, std::uint64_t seed) {
  test::Chi2Options opt;
  opt.theta_bins = 40;
  opt.phi_bins = 40;
  const test::Chi2Result r = test::chi2_test([&](double u1, double u2) { return sample_ndf(f, u1, u2); },
                                             [&](Vec3 m) { return ndf_pdf(f, m); }, kSamples, seed, opt);
  EXPECT_NEAR(r.expected_total, static_cast<double>(kSamples), 1e-6 * kSamples) << r.report;
  EXPECT_TRUE(r.passed(kAlpha)) << "tau0 " << f.tau0 << " beta " << f.beta_x << "," << f.beta_y
                                << " alpha " << kAlpha << ": " << r.report;
}
}  // namespace

TEST(MicrograinChi2Helper, IncompleteGammaKnownValues) {
  for (double x : {0.0, 0.5, 3.0, 20.0}) EXPECT_NEAR(test::regularized_gamma_q(1.0, x), std::exp(-x), 1e-14);
  for (double x : {0.1, 1.0, 4.0, 30.0}) {
    EXPECT_NEAR(test::chi2_survival(x, 1), std::erfc(std::sqrt(x / 2)), 1e-13);
    EXPECT_NEAR(test::chi2_survival(x, 2), std::exp(-x / 2), 1e-14);
    // dof 4: Q(2, x/2) = e^{-x/2}(1 + x/2)
    EXPECT_NEAR(test::chi2_survival(x, 4), std::exp(-x / 2) * (1 + x / 2), 1e-13);
  }
  // Large dof: the median of chi2_k is about k (1 - 2/(9k))^3.
  const int k = 1500;
  EXPECT_NEAR(test::chi2_survival(k * std::pow(1 - 2.0 / (9 * k), 3), k), 0.5, 1e-3);
  EXPECT_NEAR(test::regularized_gamma_p(2.5, 1.7) + test::regularized_gamma_q(2.5, 1.7), 1.0, 1e-15);
  EXPECT_NEAR(test::sidak_alpha(0.01, 1), 0.01, 1e-15);
  EXPECT_NEAR(test::sidak_alpha(0.01, 5), 1 - std::pow(0.99, 0.2), 1e-15);
}

// The helper must reject a wrong pdf: cosine-weighted samples against a uniform pdf.
TEST(MicrograinChi2Helper, RejectsAWrongPdf) {
  const test::Chi2Result r = test::chi2_test(
      [](double u1, double u2) {
        const double s = std::sqrt(u1), phi = 2 * kPi * u2;
        return Vec3{s * std::cos(phi), s * std::sin(phi), std::sqrt(1 - u1)};
      },
      [](Vec3) { return 1 / (2 * kPi); }, 100000, 1);
  EXPECT_LT(r.p_value, 1e-6) << r.report;
}

// Eq. 20 (corrected) is the inverse of Eq. 19.
TEST(MicrograinNdfSampling, ThetaInvertsCdf) {
  for (double tau0 : {0.05, 0.5, 0.98})
    for (double beta : {0.2, 1.0, 2.0})
      for (double u : {0.0, 0.1, 0.5, 0.9, 0.999}) {
        const double th = sample_ndf_theta(tau0, beta, u);
        EXPECT_NEAR(ndf_cdf_theta(tau0, beta, th), u, 1e-12);
        // the direction sampler agrees with the 1-D one for isotropic fields
        const Vec3 m = sample_ndf(isotropic_field(tau0, beta), u, 0.3);
        EXPECT_NEAR(spherical_theta(m), th, 1e-12);
        if (u > 0) {  // the azimuth is undefined at the pole
          EXPECT_NEAR(spherical_phi(m), 2 * kPi * 0.3, 1e-12);
        }
      }
}

// Eq. 20 as printed: beta sqrt(ln(1 - xi tau0) / (ln(1 - xi tau0) - ln(1 - tau0)))
// has a negative radicand on (0, 1); the sign-corrected form equals tan theta_m.
TEST(MicrograinNdfSampling, PublishedEq20HasNegativeRadicand) {
  const double tau0 = 0.5, beta = 0.7;
  for (double xi : {0.1, 0.5, 0.9}) {
    const double l = std::log(1 - xi * tau0), l0 = std::log(1 - tau0);
    EXPECT_LT(l / (l - l0), 0.0);
    EXPECT_NEAR(beta * std::sqrt(l / (l0 - l)), std::tan(sample_ndf_theta(tau0, beta, xi)), 1e-12);
  }
}

// 10^6 samples each, 40 x 40 equal-area (cos theta, phi) bins, pdf D(m) cos theta_m.
TEST(MicrograinNdfSampling, Chi2IsotropicRough) { run_chi2({0.5, 0.8, 0.8}, 11); }
TEST(MicrograinNdfSampling, Chi2IsotropicDenseSmooth) { run_chi2({0.95, 0.3, 0.3}, 12); }
TEST(MicrograinNdfSampling, Chi2IsotropicSparseSpheres) { run_chi2({0.1, 1.0, 1.0}, 13); }
TEST(MicrograinNdfSampling, Chi2Anisotropic) { run_chi2({0.6, 0.35, 1.0}, 14); }
TEST(MicrograinNdfSampling, Chi2AnisotropicSteep) { run_chi2({0.3, 2.5, 0.7}, 15); }
