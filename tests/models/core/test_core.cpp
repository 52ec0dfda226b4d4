// models/core: RNG streams, frames, warps, quadrature, triangle cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "models/core/arc_sine.h"
#include "models/core/frame.h"
#include "models/core/graded_quadrature.h"
#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/core/simd_exp.h"
#include "models/core/simd_log.h"
#include "models/core/small_angle.h"
#include "models/core/statistics.h"
#include "models/core/triangle_cut.h"
#include "models/core/warp.h"
#include "tests/models/chi2.h"

using namespace mcref;

TEST(Rng, SameSeedSameStream) {
  Rng a(stream_seed({1, 2, 3})), b(stream_seed({1, 2, 3}));
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, StreamSeedDependsOnEveryKeyAndOrder) {
  std::set<std::uint64_t> seen;
  for (std::uint64_t a = 0; a < 8; ++a)
    for (std::uint64_t b = 0; b < 8; ++b)
      for (std::uint64_t c = 0; c < 8; ++c) seen.insert(stream_seed({a, b, c}));
  EXPECT_EQ(seen.size(), 512u);
  EXPECT_NE(stream_seed({1, 2}), stream_seed({2, 1}));
}

// Seed 7, 10^6 draws: the mean of U(0,1) has stderr 1/sqrt(12e6); 4-sigma band.
TEST(Rng, UniformMeanWithinFourSigma) {
  Rng r(7);
  const int n = 1000000;
  double s = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
  }
  EXPECT_NEAR(s / n, 0.5, 4.0 / std::sqrt(12.0 * n));
}

// Seed 11: 2000 Poisson(50) draws; mean stderr sqrt(50/2000); 4-sigma band.
TEST(Rng, PoissonMeanWithinFourSigma) {
  Rng r(11);
  const int n = 2000;
  double s = 0;
  for (int i = 0; i < n; ++i) s += static_cast<double>(r.poisson(50.0));
  EXPECT_NEAR(s / n, 50.0, 4.0 * std::sqrt(50.0 / n));
}

// Streams of neighbouring chunks must not be correlated: correlation of the
// first 10^5 uniforms of chunk 0 and chunk 1 is ~N(0, 1/n); 4-sigma band.
TEST(Rng, NeighbouringStreamsUncorrelated) {
  Rng a(stream_seed({5, 0, 0, 0, 0})), b(stream_seed({5, 0, 0, 0, 1}));
  const int n = 100000;
  double sab = 0;
  for (int i = 0; i < n; ++i) sab += (a.uniform() - 0.5) * (b.uniform() - 0.5);
  const double corr = sab / n * 12.0;
  EXPECT_LT(std::fabs(corr), 4.0 / std::sqrt(n));
}

TEST(Frame, IsOrthonormalAndRoundTrips) {
  Rng r(3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 n = sample_uniform_sphere(r.uniform(), r.uniform());
    const Frame f(n);
    EXPECT_NEAR(dot(f.s, f.t), 0, 1e-12);
    EXPECT_NEAR(dot(f.s, f.n), 0, 1e-12);
    EXPECT_NEAR(length(f.s), 1, 1e-12);
    const Vec3 v{0.3, -0.2, 0.9};
    const Vec3 back = f.to_world(f.to_local(v));
    EXPECT_NEAR(length(back - v), 0, 1e-12);
  }
}

TEST(Quadrature, GaussLegendreIsExactForPolynomials) {
  GaussLegendre g(8);  // exact to degree 15
  EXPECT_NEAR(g.integrate([](double x) { return std::pow(x, 14); }, 0, 2), std::pow(2, 15) / 15, 1e-9);
  EXPECT_NEAR(integrate_composite([](double x) { return std::sin(x); }, 0, kPi), 2.0, 1e-13);
}

TEST(SmallAngle, MatchesTheLibrary) {
  double worst = 0;
  for (int k = -3000; k <= 3000; ++k) {
    const double d = k * 5e-4;  // [-1.5, 1.5]
    const SinCos r = sincos_small(d);
    worst = std::max({worst, std::fabs(r.sin - std::sin(d)), std::fabs(r.cos - std::cos(d))});
  }
  EXPECT_LT(worst, 2e-14);
  const SinCos far = sincos_small(2.5);  // outside the series' range: the library
  EXPECT_EQ(far.sin, std::sin(2.5));
  EXPECT_EQ(far.cos, std::cos(2.5));
}

TEST(SmallAngle, TurnMatchesTheLibrary) {
  double worst = 0;
  for (int k = 0; k <= 40000; ++k) {
    const double u = k / 40000.0 + (k % 7) * 1e-7;  // [0, 1], across every quarter-turn boundary
    const SinCos r = sincos_turn(u);
    worst = std::max({worst, std::fabs(r.sin - std::sin(2 * kPi * u)), std::fabs(r.cos - std::cos(2 * kPi * u))});
  }
  EXPECT_LT(worst, 3e-15);
  EXPECT_EQ(sincos_turn(0.25).cos, 0.0);  // exact quarter turns
  EXPECT_EQ(sincos_turn(0.5).sin, 0.0);
  EXPECT_EQ(sincos_turn(0.75).sin, -1.0);
  const SinCos back = sincos_turn(-0.3);  // outside [0, 2^50): the library
  EXPECT_EQ(back.sin, std::sin(2 * kPi * -0.3));
}

TEST(SmallAngle, WithinPiMatchesTheLibrary) {
  double worst = 0;
  for (int k = -40000; k <= 40000; ++k) {
    const double x = k * (kPi / 40000);  // [-pi, pi]
    const SinCos r = sincos_within_pi(x);
    worst = std::max({worst, std::fabs(r.sin - std::sin(x)), std::fabs(r.cos - std::cos(x))});
  }
  EXPECT_LT(worst, 1e-15);
  const SinCos far = sincos_within_pi(4.0);  // outside [-pi, pi]: the library
  EXPECT_EQ(far.sin, std::sin(4.0));
}

TEST(ArcSine, MatchesTheLibrary) {
  double worst = 0;
  for (int k = -100000; k <= 100000; ++k) {
    const double x = k * 1e-5;  // [-1, 1], across the switch at |x| = 1/2
    worst = std::max(worst, std::fabs(asin_series(x) - std::asin(x)));
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(asin_series(0.0), 0.0);
  EXPECT_NEAR(asin_series(1.0), kPi / 2, 1e-16);
  EXPECT_NEAR(asin_series(-1.0), -kPi / 2, 1e-16);
}

TEST(TriangleCut, FusedPointEqualsTheCutsPoint) {
  // triangle_cut_point: the point of triangle_cut_scaled(...).point(u_t) in one
  // step, for random cuts (f, q > 0, w_a anywhere in [0, 2]) and any common scale.
  Rng rng(9);
  double worst = 0;
  for (int k = 0; k < 100000; ++k) {
    const double x_a = rng.uniform() - 0.5, f = 0.05 + rng.uniform(), q = 0.05 + rng.uniform();
    const double d = 2 * (rng.uniform() - 0.5), w_a = 2 * rng.uniform(), df = (w_a * f * q - f * f) / d;
    const double scale = std::exp(10 * (rng.uniform() - 0.5)), u_t = rng.uniform();
    const TriangleCut c = triangle_cut_scaled(x_a, f, df, q, d);
    const double p = triangle_cut_point(x_a, scale * f, scale * df, scale * q, scale * d, u_t);
    worst = std::max(worst, std::fabs(p - c.point(u_t)) / (1 + std::fabs(c.x_b - x_a)));
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_EQ(triangle_cut_point(0.3, 0.0, 1.0, 1.0, 0.5, 0.7), 0.3);  // an end of the domain
}

// The branch-free version gives sincos_turn's bits on [0, 1].
TEST(SmallAngle, TurnUnitEqualsTurn) {
  for (int k = 0; k <= 40000; ++k) {
    const double u = std::min(1.0, k / 40000.0 + (k % 7) * 1e-7);
    const SinCos a = sincos_turn_unit(u), b = sincos_turn(u);
    ASSERT_EQ(a.sin, b.sin) << u;
    ASSERT_EQ(a.cos, b.cos) << u;
  }
}

// Within 2 ulp of the library's log over normal numbers of every exponent,
// near 1 (where log -> 0) and at the walk's arguments 2^-52 k.
TEST(SimdLog, MatchesTheLibrary) {
  Rng rng(7);
  double worst = 0;
  for (int k = 0; k < 300000; ++k) {
    double x;
    if (k % 3 == 0) x = std::ldexp(0.5 + 0.5 * rng.uniform(), static_cast<int>(rng.below(2040)) - 1020);
    else if (k % 3 == 1) x = 1 + (rng.uniform() - 0.5) * 1e-6;
    else x = static_cast<double>((rng.next_u64() >> 12) + 1) * 0x1p-52;
    const double a = simd_log(x), b = std::log(x);
    if (b == 0) {
      EXPECT_EQ(a, 0.0);
      continue;
    }
    worst = std::max(worst, std::fabs(a - b) / std::fabs(b));
  }
  EXPECT_LE(worst, 2 * 0x1p-52);  // (measured: 1 ulp)
  EXPECT_EQ(simd_log(1.0), 0.0);
}

// simd_exp_nonpositive against std::exp: 3 x 10^6 draws (seed 11) over [-708, 0],
// [-1, 0] and [-1e-3, 0], within 1 ulp (fdlibm's bound for its algorithm); exact at
// 0; 0 below -708 and at -inf; NaN kept.
TEST(SimdExp, WithinAnUlpOfLibm) {
  Rng rng(11);
  double worst = 0;
  for (int k = 0; k < 3000000; ++k) {
    const double scale = k % 3 == 0 ? 708.0 : k % 3 == 1 ? 1.0 : 1e-3;
    const double x = -scale * rng.uniform();
    const double a = simd_exp_nonpositive(x), b = std::exp(x);
    ASSERT_GT(b, 0.0);
    worst = std::max(worst, std::fabs(a - b) / b);
  }
  EXPECT_LE(worst, 0x1p-52);  // (measured: 0.9998 ulp of 2^-52 relative)
  EXPECT_EQ(simd_exp_nonpositive(0.0), 1.0);
  EXPECT_EQ(simd_exp_nonpositive(-0.0), 1.0);
  EXPECT_EQ(simd_exp_nonpositive(-708.0), std::exp(-708.0));
  EXPECT_EQ(simd_exp_nonpositive(-708.5), 0.0);
  EXPECT_EQ(simd_exp_nonpositive(-1e300), 0.0);
  EXPECT_EQ(simd_exp_nonpositive(-INFINITY), 0.0);
  EXPECT_TRUE(std::isnan(simd_exp_nonpositive(NAN)));
}

TEST(TriangleCut, MapsUniformSamplesOntoTheTarget) {
  // Target f(x) = 2x on [0, 1] (F = x^2) from the uniform q = 1 (x_a = u_s):
  // every cut is valid, and F(x) of the mapped samples is uniform. Chi-square
  // over 50 equal bins, 2e5 samples, seed 5, at alpha = 0.001.
  Rng rng(5);
  const int bins = 50, n = 200000;
  std::vector<double> count(bins, 0);
  int invalid = 0;
  for (int k = 0; k < n; ++k) {
    const double u_s = rng.uniform(), u_t = rng.uniform();
    const TriangleCut c = triangle_cut(u_s, u_s, 2 * u_s, u_s * u_s, 2.0, 1.0);
    invalid += !c.valid();
    const double x = c.point(u_t);
    count[std::min(bins - 1, static_cast<int>(x * x * bins))] += 1;
  }
  EXPECT_EQ(invalid, 0);
  double chi2 = 0;
  const double e = static_cast<double>(n) / bins;
  for (double c : count) chi2 += (c - e) * (c - e) / e;
  EXPECT_GT(chi2_survival(chi2, bins - 1), 0.001) << "chi2 " << chi2;
}

// Both cosine-hemisphere samplers (polar map; Malley by rejection in the disc)
// against pdf = cos(theta)/pi: chi^2 on 32 x 64 equal-area cells, 10^6
// samples each, seeds 5 and 6, family-wise alpha 1e-3 (Sidak over the two).
TEST(Warp, CosineHemisphereSamplersMatchTheirDensity) {
  const double alpha = mcref::test::sidak_alpha(1e-3, 2);
  auto pdf = [](Vec3 w) { return w.z > 0 ? w.z / kPi : 0.0; };
  const auto polar =
      mcref::test::chi2_test([](double u1, double u2) { return sample_cosine_hemisphere(u1, u2); }, pdf, 1000000, 5);
  EXPECT_TRUE(polar.passed(alpha)) << polar.report;
  Rng rng(6);
  const auto rejection = mcref::test::chi2_test([&](double, double) { return sample_cosine_hemisphere(rng); }, pdf, 1000000, 6);
  EXPECT_TRUE(rejection.passed(alpha)) << rejection.report;
}

// The uniform sphere by Marsaglia's method against 1/(4 pi), and the
// unnormalised cosine direction n + (uniform sphere point), brought to n's
// frame and normalised, against cos(theta)/pi for a vertical, a tilted and a
// nearly horizontal n: chi^2 on 32 x 64 equal-area cells, 10^6 samples each,
// seeds 7-10, family-wise alpha 1e-3 (Sidak over the four).
TEST(Warp, SphereAndCosineAboutNormalMatchTheirDensity) {
  const double alpha = mcref::test::sidak_alpha(1e-3, 4);
  mcref::test::Chi2Options sphere_cells;
  sphere_cells.hemisphere = false;
  Rng rng(7);
  const auto sphere = mcref::test::chi2_test([&](double, double) { return sample_uniform_sphere(rng); },
                                             [](Vec3) { return 1 / (4 * kPi); }, 1000000, 7, sphere_cells);
  EXPECT_TRUE(sphere.passed(alpha)) << sphere.report;
  std::uint64_t seed = 8;
  for (const Vec3 n : {Vec3{0, 0, 1}, normalize(Vec3{0.3, -0.5, 0.8}), normalize(Vec3{1, 0.2, 1e-3})}) {
    const Frame frame(n);
    Rng r(seed);
    const auto cosine = mcref::test::chi2_test(
        [&](double, double) { return frame.to_local(normalize(sample_cosine_about(n, r))); },
        [](Vec3 w) { return w.z > 0 ? w.z / kPi : 0.0; }, 1000000, seed);
    EXPECT_TRUE(cosine.passed(alpha)) << "n = (" << n.x << ", " << n.y << ", " << n.z << ")\n" << cosine.report;
    ++seed;
  }
}

// integrate_adaptive_graded: end behaviours |x - a|^(3/2) and sqrt(b - x) (the
// kinks of the G_dist polar integrand) are integrated to 1e-12 against their
// closed forms, with fewer evaluations than the plain adaptive rule needs.
TEST(Quadrature, GradedAdaptiveHandlesEndKinks) {
  const double a = 0.3, b = 1.1;
  long graded_calls = 0, plain_calls = 0;
  auto f = [&](double x, long& calls) {
    ++calls;
    return std::pow(x - a, 1.5) * std::cos(x) + std::sqrt(std::fmax(0.0, b - x));
  };
  // ∫ (x - a)^(3/2) cos x dx has no elementary form: a 2^20-panel reference of that part.
  const double exact_sqrt = 2.0 / 3.0 * std::pow(b - a, 1.5);
  const double ref = integrate_composite([&](double x) { return std::pow(x - a, 1.5) * std::cos(x); }, a, b, 1 << 14, 16) +
                     exact_sqrt;
  const double g = integrate_adaptive_graded([&](double x) { return f(x, graded_calls); }, a, b, 1e-12);
  const double p = integrate_adaptive([&](double x) { return f(x, plain_calls); }, a, b, 1e-12);
  EXPECT_NEAR(g, ref, 1e-12);
  EXPECT_NEAR(p, ref, 1e-11);
  EXPECT_LT(graded_calls, plain_calls);
  // A smooth integrand is unchanged by the map.
  EXPECT_NEAR(integrate_adaptive_graded([](double x) { return std::exp(x); }, 0.0, 2.0, 1e-13), std::exp(2.0) - 1, 1e-12);
}
