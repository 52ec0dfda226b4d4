// models/micrograin: the vNDF sampler (vNDF paper Listings 1–4): the tabulated
// sigma^-1, the triangle-cut phi step, and chi-square tests of the sampled
// normals against visible_ndf (Eq. 6/11–13). Fixed seeds; Sidak-corrected.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "chi2.h"
#include "models/core/quadrature.h"
#include "models/core/rng.h"
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
  const test::Chi2Result r = test::chi2_test([&](double u1, double u2, double u3) { return sampler().sample(f, i, u1, u2, u3); },
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

TEST(MicrograinVndfSampler, TriangleCutsNeverCross) {
  // The triangle-cut map is exact only if every cut is a proper sliver
  // (0 <= w_a <= 2), ends inside [-phi_q, phi_q] and lies under the curve
  // (Eq. 26). Checked on a 60 x 60 grid of (theta_i', theta') and 2000 cuts each.
  int bad = 0;
  double w_lo = 2, w_hi = 0;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      const double ti = (i + 0.5) / 60 * kPi / 2, tm = (j + 0.5) / 60 * kPi / 2;
      const PhiConditional p(Vec3{std::sin(ti), 0, std::cos(ti)}, std::cos(tm));
      for (int k = 0; k < 2000; ++k) {
        const TriangleCut c = p.cut((k + 0.5) / 2000);
        w_lo = std::min(w_lo, c.w_a);
        w_hi = std::max(w_hi, c.w_a);
        // ... and the step along it stays where PhiConditional::sample's small-angle sincos is exact.
        bool ok = c.valid() && std::fabs(c.x_b) <= p.phi_q * (1 + 1e-12) && std::fabs(c.x_b - c.x_a) <= 1.5;
        for (int q = 0; q <= 20 && ok; ++q) {
          const double t = q / 20.0, x = c.x_a + t * (c.x_b - c.x_a);
          ok = (1 - t) * p.pdf(c.x_a) <= p.pdf(x) * (1 + 1e-9) + 1e-12;
        }
        bad += !ok;
      }
    }
  EXPECT_EQ(bad, 0);
  RecordProperty("w_a_range", std::to_string(w_lo) + " " + std::to_string(w_hi));
}

TEST(MicrograinVndfSampler, PhiFollowsConditionalPdf) {
  // Probability integral transform: if phi has the density of Eq. 26, its
  // CDF value (Eq. 22) is uniform. Chi-square over 64 equal bins, 2e5 samples
  // per case, seeds 31.., Sidak-corrected over the cases at alpha = 0.01.
  const double cases[][2] = {{20, 10}, {20, 80}, {60, 10}, {60, 45}, {60, 85}, {85, 5}, {85, 60}, {89, 89}};
  const int n_cases = sizeof(cases) / sizeof(cases[0]), bins = 64, n = 200000;
  const double alpha = test::sidak_alpha(0.01, n_cases);
  std::uint64_t seed = 31;
  for (const auto& cs : cases) {
    const double ti = cs[0] * kPi / 180, tm = cs[1] * kPi / 180;
    const Vec3 iu{std::sin(ti), 0, std::cos(ti)};
    const PhiConditional p(iu, std::cos(tm));
    std::vector<double> count(bins, 0);
    Rng rng(seed++);
    for (int k = 0; k < n; ++k) {
      const double u_s = rng.uniform(), u_t = rng.uniform();
      const double phi = VndfSampler::sample_phi(iu, std::cos(tm), u_s, u_t);
      ASSERT_LE(std::fabs(phi), p.phi_q);
      count[std::min(bins - 1, static_cast<int>(p.cdf(phi) * bins))] += 1;
    }
    double chi2 = 0;
    const double e = static_cast<double>(n) / bins;
    for (double c : count) chi2 += (c - e) * (c - e) / e;
    const double pv = test::chi2_survival(chi2, bins - 1);
    EXPECT_GT(pv, alpha) << "theta_i " << cs[0] << " theta " << cs[1] << ": chi2 " << chi2 << " / " << bins - 1;
  }
}

TEST(MicrograinVndfSampler, TentIsAUnitMassDensity) {
  // The tent (Eq. 28, slope sign corrected) and its inverse CDF (Eq. 31):
  // ends at +-phi_q with height h0, unit mass, symmetric inverse.
  const PhiConditional p(Vec3{std::sin(1.2), 0, std::cos(1.2)}, std::cos(1.0));
  EXPECT_NEAR(p.tent_pdf(p.phi_q), p.h0(), 1e-14);
  EXPECT_NEAR(p.tent_inverse(0.5), 0.0, 1e-14);
  EXPECT_NEAR(p.tent_inverse(1.0), p.phi_q, 1e-12);
  EXPECT_NEAR(p.tent_inverse(0.2), -p.tent_inverse(0.8), 1e-12);
  // The tent's CDF by quadrature on each side of its peak (Eq. 29).
  const GaussLegendre rule(8);
  auto tent_cdf = [&](double x) {
    auto pdf = [&](double y) { return p.tent_pdf(y); };
    return rule.integrate(pdf, -p.phi_q, std::min(x, 0.0)) + (x > 0 ? rule.integrate(pdf, 0.0, x) : 0.0);
  };
  EXPECT_NEAR(tent_cdf(p.phi_q), 1.0, 1e-12);
  for (double u : {0.05, 0.3, 0.7, 0.99}) EXPECT_NEAR(tent_cdf(p.tent_inverse(u)), u, 1e-12);  // Eq. 31 inverts Eq. 30
}

TEST(MicrograinVndfSampler, Chi2Isotropic20) { run_chi2({0.5, 0.8, 0.8}, 20, 0, 21); }
TEST(MicrograinVndfSampler, Chi2Isotropic60) { run_chi2({0.7, 1.0, 1.0}, 60, 30, 22); }
TEST(MicrograinVndfSampler, Chi2DenseGrazing80) { run_chi2({0.95, 0.3, 0.3}, 80, 0, 23); }
TEST(MicrograinVndfSampler, Chi2SparseTall85) { run_chi2({0.2, 3.0, 3.0}, 85, 0, 24); }
TEST(MicrograinVndfSampler, Chi2Anisotropic) { run_chi2({0.6, 0.35, 1.0}, 50, 40, 25); }
TEST(MicrograinVndfSampler, Chi2AnisotropicSteep) { run_chi2({0.3, 2.5, 0.7}, 70, 120, 26); }
