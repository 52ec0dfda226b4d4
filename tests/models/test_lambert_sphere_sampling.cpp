// models/lambert_sphere: phase-function samplers (d'Eon 2021, Eq. 5 and Eq. 6).
//
// chi^2 goodness of fit over mu with B equal-probability bins under the exact
// density (edges F^{-1}(k/B) from the exact CDF), fixed seeds, N = 10^6
// samples, significance 0.01 for the file, Sidak-corrected over its 2 chi^2
// tests that must pass (Eq. 5 at 10^6, Eq. 6 at 10^5): alpha = 1 - 0.99^(1/2). p-value from the chi^2 distribution,
// Q(dof/2, chi^2/2), the regularised incomplete gamma of models/core/statistics.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "models/core/rng.h"
#include "models/core/statistics.h"
#include "models/core/vec.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/phase_sampling.h"

namespace ls = mcref::lambert_sphere;

namespace {

void record(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::printf("[measured] %s = %.6g\n", key.c_str(), value);
}

// Q(a, x), the regularised upper incomplete gamma of models/core/statistics.h.
using mcref::regularized_gamma_q;
const auto gamma_q = [](double a, double x) { return regularized_gamma_q(a, x); };

struct Chi2 {
  double statistic = 0, p_value = 1;
  int dof = 0;
};

// Bins of equal probability under the exact density of mu.
template <class Sampler>
Chi2 chi2_equal_probability(int bins, long samples, Sampler&& sample) {
  std::vector<double> edges(bins + 1);
  for (int k = 0; k <= bins; ++k) edges[k] = ls::phase_inverse_cdf(static_cast<double>(k) / bins);
  std::vector<long> count(bins, 0);
  for (long i = 0; i < samples; ++i) {
    const double mu = sample();
    int k = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), mu) - edges.begin()) - 1;
    if (k < 0) k = 0;
    if (k >= bins) k = bins - 1;
    ++count[k];
  }
  const double expected = static_cast<double>(samples) / bins;
  Chi2 r;
  for (long c : count) r.statistic += (c - expected) * (c - expected) / expected;
  r.dof = bins - 1;
  r.p_value = gamma_q(0.5 * r.dof, 0.5 * r.statistic);
  return r;
}

const double kAlpha = 1 - std::pow(0.99, 1.0 / 2.0);  // Sidak over the 2 chi^2 tests of this file
constexpr int kBins = 100;
constexpr long kSamples = 1000000;

}  // namespace

// The local incomplete gamma against closed forms: Q(1, x) = e^-x,
// Q(1/2, x) = erfc(sqrt x), and the chi^2 median for 99 dof (~98.334).
TEST(lambert_sphere_Sampling, IncompleteGammaClosedForms) {
  for (double x : {0.1, 1.0, 3.0, 20.0}) {
    EXPECT_NEAR(gamma_q(1.0, x), std::exp(-x), 1e-14);
    EXPECT_NEAR(gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-14);
  }
  EXPECT_NEAR(gamma_q(49.5, 0.5 * 98.334), 0.5, 1e-3);
}

// Eq. 5, exact sampler: must pass.
TEST(lambert_sphere_Sampling, ExactSamplerEq5PassesChi2) {
  mcref::Rng rng(mcref::stream_seed({2021, 5}));
  const Chi2 r = chi2_equal_probability(kBins, kSamples, [&] {
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    return ls::sample_phase_cosine_exact(u1, u2, u3);
  });
  record("eq5_chi2", r.statistic);
  record("eq5_p_value", r.p_value);
  EXPECT_GT(r.p_value, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

// Eq. 6, approximate inverse CDF. The paper claims |mu - mu_exact| < 0.0005.
// MEASURED: max error 5.739e-4 at xi = 0.99943, so the claim FAILS (by 15 %);
// we assert the measured bound. Away from the forward tail it is below the claim.
TEST(lambert_sphere_Sampling, ApproximateInverseCdfEq6Error) {
  const ls::InverseCdfError e = ls::approximate_inverse_cdf_max_error(200000);
  record("eq6_max_abs_error", e.max_abs_error);
  record("eq6_max_abs_error_at_xi", e.xi);
  EXPECT_LT(e.max_abs_error, 5.75e-4);  // measured 5.739e-4 (claimed < 5e-4: not met)
  EXPECT_GT(e.max_abs_error, 5e-4);     // the claim fails: keep this visible
  double below_099 = 0;
  for (int i = 0; i <= 99000; ++i) {
    const double xi = i / 100000.0;
    below_099 = std::fmax(below_099, std::fabs(ls::sample_phase_cosine_approx(xi) - ls::phase_inverse_cdf(xi)));
  }
  record("eq6_max_abs_error_xi_le_0.99", below_099);
  EXPECT_LT(below_099, 5e-4);
  // Monotone and onto [-1, 1].
  EXPECT_EQ(ls::sample_phase_cosine_approx(0.0), -1.0);
  EXPECT_EQ(ls::sample_phase_cosine_approx(1.0), 1.0);
  for (int i = 1; i <= 100000; ++i)
    ASSERT_GT(ls::sample_phase_cosine_approx(i / 100000.0), ls::sample_phase_cosine_approx((i - 1) / 100000.0));
}

// Eq. 6 as a sampler against the exact density. Its bin probabilities q_k
// differ from 1/B by O(pdf x 5e-4), so the chi^2 statistic exceeds its dof by
// lambda = N B sum_k (q_k - 1/B)^2 on average (q_k from the exact inverse of
// Eq. 6 by bisection). MEASURED: lambda = 15.8 per 10^6 samples with 100 bins,
// i.e. Eq. 6 becomes detectable (lambda = critical excess 40) at ~2.5 10^6
// samples. So: N = 10^5 must pass (lambda = 1.6, counted in the Sidak family);
// N = 10^7 must be rejected (lambda = 158, chi^2 ~ 257 +- 29 against 139).
TEST(lambert_sphere_Sampling, ApproximateSamplerEq6AgainstExactDensity) {
  auto approx_cdf = [](double mu) {  // inverse of Eq. 6 by bisection (Eq. 6 is increasing)
    double lo = 0, hi = 1;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (ls::sample_phase_cosine_approx(mid) < mu ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  double excess_per_sample = 0;
  for (int k = 0; k < kBins; ++k) {
    const double q = approx_cdf(ls::phase_inverse_cdf(static_cast<double>(k + 1) / kBins)) -
                     approx_cdf(ls::phase_inverse_cdf(static_cast<double>(k) / kBins));
    excess_per_sample += (q - 1.0 / kBins) * (q - 1.0 / kBins) * kBins;
  }
  const double critical_excess = 139.0 - 99.0;  // chi^2_99 quantile at 1 - 0.005 is ~139
  record("eq6_chi2_excess_per_1e6_samples", excess_per_sample * 1e6);
  record("eq6_samples_for_detection_100_bins", critical_excess / excess_per_sample);
  EXPECT_NEAR(excess_per_sample * 1e6, 15.76, 0.05);  // measured (deterministic)

  mcref::Rng rng(mcref::stream_seed({2021, 6}));
  auto sampler = [&] { return ls::sample_phase_cosine_approx(rng.uniform()); };
  const Chi2 small = chi2_equal_probability(kBins, 100000, sampler);
  record("eq6_p_value_1e5", small.p_value);
  EXPECT_GT(small.p_value, kAlpha) << "chi2 " << small.statistic;
  const Chi2 mid = chi2_equal_probability(kBins, 1000000, sampler);
  record("eq6_p_value_1e6", mid.p_value);
  const Chi2 large = chi2_equal_probability(kBins, 10000000, sampler);
  record("eq6_chi2_1e7", large.statistic);
  record("eq6_p_value_1e7", large.p_value);
  EXPECT_LT(large.p_value, kAlpha) << "Eq. 6 should be detected at N = 10^7";
}

// Directions: exact cosine to the propagation direction, unit length, and the
// mean scattered direction g d (g = -4/9) within 4 standard errors per axis
// (per-axis variance <= 1, so stderr <= 1/sqrt(N)); N = 2 10^5, fixed seed.
TEST(lambert_sphere_Sampling, ScatteredDirection) {
  const mcref::Vec3 d = mcref::normalize(mcref::Vec3(0.3, -0.5, 0.8));
  mcref::Rng rng(mcref::stream_seed({2021, 7}));
  const int n = 200000;
  mcref::Vec3 sum;
  for (int i = 0; i < n; ++i) {
    const double mu = ls::sample_phase_cosine_exact(rng.uniform(), rng.uniform(), rng.uniform());
    const mcref::Vec3 w = ls::scattered_direction(d, mu, rng.uniform());
    ASSERT_NEAR(mcref::length(w), 1.0, 1e-12);
    ASSERT_NEAR(mcref::dot(w, d), mu, 1e-12);
    sum = sum + w;
  }
  const mcref::Vec3 mean = sum / n, expect = d * ls::kMeanCosine;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(mean[a], expect[a], 4 / std::sqrt(static_cast<double>(n))) << "axis " << a;
}
