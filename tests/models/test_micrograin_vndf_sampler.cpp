// models/micrograin: the vNDF sampler (vNDF paper Listings 1–4): the tabulated
// sigma^-1, the exact phi inversion, and chi-square tests of the sampled
// normals against visible_ndf (Eq. 6/11–13). Fixed seeds; Sidak-corrected.
#include <gtest/gtest.h>

#include <cmath>

#include "chi2.h"
#include "models/micrograin/projected_area.h"
#include "models/micrograin/visible_ndf.h"
#include "models/micrograin/vndf_sampler.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {

constexpr int kChi2Tests = 6;
const double kAlpha = test::sidak_alpha(0.01, kChi2Tests);

const VndfSampler& sampler() {
  static const VndfSampler s;
  return s;
}

void run_chi2(const GrainField& f, double theta_i_deg, double phi_i_deg, std::uint64_t seed) {
  const Vec3 i = spherical_direction(theta_i_deg * kPi / 180, phi_i_deg * kPi / 180);
  test::Chi2Options opt;
  opt.theta_bins = 40;
  opt.phi_bins = 40;
  const test::Chi2Result r = test::chi2_test([&](double u1, double u2) { return sampler().sample(f, i, u1, u2); },
                                             [&](Vec3 m) { return visible_ndf(f, i, m); }, 1000000, seed, opt);
  EXPECT_NEAR(r.expected_total, 1e6, 2e-3 * 1e6) << r.report;
  EXPECT_TRUE(r.passed(kAlpha)) << "tau0 " << f.tau0 << " beta " << f.beta_x << "," << f.beta_y << " theta_i "
                                << theta_i_deg << ": " << r.report;
}

}  // namespace

TEST(MicrograinVndfSampler, TabulatedInverseOfSigma) {
  double worst = 0;
  for (double ti : {10.0, 35.0, 60.0, 80.0, 88.0}) {
    const double c = std::cos(ti * kPi / 180), s = std::sin(ti * kPi / 180);
    for (int k = 0; k < 50; ++k) {
      const double h = s * (k + 0.5) / 50;
      const double area = projected_cap_area(Vec3{s, 0, c}, h);
      worst = std::max(worst, std::fabs(sampler().inverse_sigma(c, area) - h));
    }
  }
  EXPECT_LT(worst, 2e-3);
  RecordProperty("max_abs_h_error", std::to_string(worst));
}

TEST(MicrograinVndfSampler, PhiInvertsConditionalCdf) {
  for (double ti : {20.0, 60.0, 85.0})
    for (double tm : {10.0, 45.0, 80.0}) {
      const double a = ti * kPi / 180, b = tm * kPi / 180;
      const Vec3 iu{std::sin(a), 0, std::cos(a)};
      for (double xi : {0.01, 0.3, 0.5, 0.77, 0.99}) {
        const double phi = VndfSampler::sample_phi(iu, std::cos(b), xi);
        EXPECT_NEAR(visible_ndf_conditional_cdf(a, b, phi), xi, 1e-9) << ti << " " << tm << " " << xi;
      }
    }
}

TEST(MicrograinVndfSampler, TentIsAUnitMassDensity) {
  // Inverse of the tent CDF: monotone, symmetric, ends at +-phi_q.
  const double phq = 2.0, h0 = 0.1;
  EXPECT_NEAR(tent_inverse(phq, h0, 0.5), 0.0, 1e-14);
  EXPECT_NEAR(tent_inverse(phq, h0, 1.0), phq, 1e-12);
  EXPECT_NEAR(tent_inverse(phq, h0, 0.2), -tent_inverse(phq, h0, 0.8), 1e-12);
}

TEST(MicrograinVndfSampler, Chi2Isotropic20) { run_chi2({0.5, 0.8, 0.8}, 20, 0, 21); }
TEST(MicrograinVndfSampler, Chi2Isotropic60) { run_chi2({0.7, 1.0, 1.0}, 60, 30, 22); }
TEST(MicrograinVndfSampler, Chi2DenseGrazing80) { run_chi2({0.95, 0.3, 0.3}, 80, 0, 23); }
TEST(MicrograinVndfSampler, Chi2SparseTall85) { run_chi2({0.2, 3.0, 3.0}, 85, 0, 24); }
TEST(MicrograinVndfSampler, Chi2Anisotropic) { run_chi2({0.6, 0.35, 1.0}, 50, 40, 25); }
TEST(MicrograinVndfSampler, Chi2AnisotropicSteep) { run_chi2({0.3, 2.5, 0.7}, 70, 120, 26); }
