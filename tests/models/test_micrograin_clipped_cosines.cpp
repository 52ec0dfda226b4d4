// models/micrograin/clipped_cosines.h: the closed-form ring integral of
// max(0, p) max(0, q) for sinusoids p, q, against a quadrature that finds the
// zeros itself (half_angle_zeros.h) and integrates each piece with 24-point Gauss-Legendre (exact to rounding for
// these smooth pieces).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/micrograin/clipped_cosines.h"
#include "tests/models/half_angle_zeros.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {

double value(const Sinusoid& p, double a) { return p.A + p.B * std::cos(a) + p.C * std::sin(a); }

double reference(const Sinusoid& p, const Sinusoid& q) {
  const auto f = [&](double a) { return std::max(0.0, value(p, a)) * std::max(0.0, value(q, a)); };
  std::vector<double> cuts{0.0, 2 * kPi};
  for (const Sinusoid* s : {&p, &q}) add_half_angle_zeros(*s, cuts);
  std::sort(cuts.begin(), cuts.end());
  static const GaussLegendre g(24);
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) sum += g.integrate(f, cuts[k], cuts[k + 1]);
  return sum;
}

}  // namespace

TEST(MicrograinClippedCosines, SpecialCases) {
  // Both positive everywhere: ∫ (2 + cos a)(3 + sin a) = 2 pi 6.
  EXPECT_NEAR(clipped_product_integral({2, 1, 0}, {3, 0, 1}), 12 * kPi, 1e-13);
  // One negative everywhere: 0 (the other positive).
  EXPECT_EQ(clipped_product_integral({-2, 1, 0}, {3, 0, 1}), 0.0);
  // p = q = cos a: ∫ over |a| < pi/2 of cos^2 = pi / 2.
  EXPECT_NEAR(clipped_product_integral({0, 1, 0}, {0, 1, 0}), kPi / 2, 1e-14);
  // p = cos a, q = -cos a: disjoint half rings, 0 up to rounding.
  EXPECT_NEAR(clipped_product_integral({0, 1, 0}, {0, -1, 0}), 0.0, 1e-15);
}

// Seed 15, 20000 random pairs: coefficients uniform in [-1, 1], and one in
// four pairs nearly tangent (|A| within 1e-6 of R) or nearly equal (q = p + 1e-9).
TEST(MicrograinClippedCosines, MatchesQuadratureReference) {
  Rng rng(15);
  const auto u = [&] { return 2 * rng.uniform() - 1; };
  int nonzero = 0;
  for (int k = 0; k < 20000; ++k) {
    Sinusoid p{u(), u(), u()}, q{u(), u(), u()};
    if (k % 4 == 1) p.A = std::copysign(std::hypot(p.B, p.C) * (1 - 1e-6 * rng.uniform()), p.A);
    if (k % 4 == 2) q = {p.A + 1e-9, p.B, p.C - 1e-9};
    const double c = clipped_product_integral(p, q), r = reference(p, q);
    const double scale = (std::fabs(p.A) + std::hypot(p.B, p.C)) * (std::fabs(q.A) + std::hypot(q.B, q.C));
    ASSERT_NEAR(c, r, 1e-12 * scale) << k << ": p " << p.A << " " << p.B << " " << p.C << ", q " << q.A << " " << q.B << " " << q.C;
    nonzero += r > 1e-3 * scale;
  }
  EXPECT_GT(nonzero, 5000);  // the comparison is not mostly 0 against 0
}
