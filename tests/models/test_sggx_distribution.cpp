// SGGX distribution (Heitz 2015; SpongeCake Eq. 3, 4, 7): matrix helpers,
// constructors, normalisation of D by projected area, the specular flake
// phase function's normalisation, reciprocity and isotropic limit.
// Quadrature accuracy: integrate_sphere with 32 x 64 panels of 8 x 8 points.
// Measured against 64 x 128 panels over all cases below, its error is
// <= 7e-11 (the worst case is alpha = 0.1); each integral is also evaluated at
// 24 x 48 panels (error <= 3.2e-9) and the two must agree to 1e-8, which is
// the tolerance used for every quadrature comparison.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "models/core/frame.h"
#include "models/core/rng.h"
#include "models/core/warp.h"
#include "models/sggx/flake_phase.h"
#include "models/sggx/mat3.h"
#include "models/sggx/sggx_distribution.h"
#include "tests/models/sggx_quadrature.h"

namespace {

using mcref::Vec3;
using mcref::kPi;
namespace sg = mcref::sggx;

constexpr double kQuadTol = 1e-8;

const Vec3 kTilted = mcref::spherical_direction(0.7, 0.5);  // tilted orientation w_p

struct Case {
  bool fiber;
  double alpha;
  Vec3 wp;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  for (bool fiber : {false, true})
    for (double a : {0.1, 0.5, 1.0})
      for (Vec3 wp : {Vec3{0, 0, 1}, kTilted}) c.push_back({fiber, a, wp});
  return c;
}

sg::Sggx make(const Case& c) { return c.fiber ? sg::fiber_like(c.alpha, c.wp) : sg::surface_like(c.alpha, c.wp); }

std::string name(const Case& c) {
  return std::string(c.fiber ? "fiber" : "surface") + " alpha=" + std::to_string(c.alpha) +
         " wp=(" + std::to_string(c.wp.x) + "," + std::to_string(c.wp.y) + "," + std::to_string(c.wp.z) + ")";
}

const std::vector<Vec3> kDirections = {mcref::spherical_direction(0.2, 0.3),
                                       mcref::spherical_direction(1.1, 2.0),
                                       mcref::spherical_direction(1.45, 4.0),
                                       mcref::spherical_direction(2.5, 5.5)};

// Integral at full and half resolution; returns the full one and checks agreement.
template <class F>
double sphere_integral(F&& f, Vec3 pole, double theta_max = kPi) {
  const double fine = mcref::sggx_test::integrate_sphere(f, pole, 32, 64, 8, theta_max);
  const double coarse = mcref::sggx_test::integrate_sphere(f, pole, 24, 48, 8, theta_max);
  EXPECT_NEAR(fine, coarse, kQuadTol * std::fmax(1.0, std::fabs(fine))) << "quadrature not converged";
  return fine;
}

TEST(sggxMat3, InverseDeterminantCholesky) {
  sg::Mat3 a;
  const double v[3][3] = {{4, 1, 0.5}, {1, 3, -0.2}, {0.5, -0.2, 2}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a(i, j) = v[i][j];
  EXPECT_LT(sg::max_abs_difference(a * sg::inverse(a), sg::identity3()), 1e-14);
  const double det = 4 * (6 - 0.04) - 1 * (2 + 0.1) + 0.5 * (-0.2 - 1.5);
  EXPECT_NEAR(sg::determinant(a), det, 1e-13);
  sg::Mat3 l;
  ASSERT_TRUE(sg::cholesky_lower(a, l));
  EXPECT_EQ(l(0, 1), 0.0);
  EXPECT_LT(sg::max_abs_difference(l * sg::transpose(l), a), 1e-14);
  EXPECT_FALSE(sg::cholesky_lower(sg::diagonal(1, -1, 1), l));
}

TEST(sggxDistribution, ConstructorsMatchRotatedDiagonal) {
  // S = R diag(.) R^T with R = [s t n] mapping z to w_p.
  const mcref::Frame f(kTilted);
  const sg::Mat3 r = sg::from_columns(f.s, f.t, f.n);
  for (double a : {0.1, 0.5, 1.0}) {
    const sg::Mat3 surf = r * sg::diagonal(a * a, a * a, 1) * sg::transpose(r);
    const sg::Mat3 fib = r * sg::diagonal(1, 1, a * a) * sg::transpose(r);
    EXPECT_LT(sg::max_abs_difference(sg::surface_like(a, kTilted).S, surf), 1e-14);
    EXPECT_LT(sg::max_abs_difference(sg::fiber_like(a, kTilted).S, fib), 1e-14);
    EXPECT_NEAR(sg::surface_like(a, kTilted).sqrt_det, a * a, 1e-14);
    EXPECT_NEAR(sg::fiber_like(a, kTilted).sqrt_det, a, 1e-14);
  }
  EXPECT_THROW(sg::surface_like(0, {0, 0, 1}), std::invalid_argument);
  EXPECT_THROW(sg::fiber_like(0.5, {0, 0, 0}), std::invalid_argument);
}

TEST(sggxDistribution, SurfaceLikeIsGgx) {
  // D = 1 / (pi a^2 cos^4 (1 + tan^2/a^2)^2) (GGX, Walter 2007) for w_p = z.
  for (double a : {0.1, 0.5, 1.0}) {
    const sg::Sggx s = sg::surface_like(a, {0, 0, 1});
    for (double t : {0.0, 0.3, 1.0, 1.5}) {
      const double c = std::cos(t), t2 = std::tan(t) * std::tan(t);
      const double ggx = 1 / (kPi * a * a * c * c * c * c * (1 + t2 / (a * a)) * (1 + t2 / (a * a)));
      EXPECT_NEAR(sg::ndf(s, mcref::spherical_direction(t, 0.7)), ggx, 1e-12 * ggx);
    }
    EXPECT_NEAR(sg::projected_area(s, {0, 0, 1}), 1.0, 1e-15);
  }
}

TEST(sggxDistribution, ProjectedAreaIsIntegralOfClampedCosine) {
  // Eq. 3: sigma(w) = \int <w.m>^+ D(m) dm, and \int |w.m| D dm = 2 sigma(w).
  for (const Case& c : cases()) {
    const sg::Sggx s = make(c);
    for (Vec3 w : kDirections) {
      const double sigma = sg::projected_area(s, w);
      const double half = sphere_integral([&](Vec3 m) { return dot(w, m) * sg::ndf(s, m); }, w, kPi / 2);
      const double full = sphere_integral([&](Vec3 m) { return std::fabs(dot(w, m)) * sg::ndf(s, m); }, w);
      EXPECT_NEAR(half, sigma, kQuadTol * sigma) << name(c);
      EXPECT_NEAR(full, 2 * sigma, 2 * kQuadTol * sigma) << name(c);
    }
  }
}

TEST(sggxDistribution, VisibleNdfIntegratesToOne) {
  for (const Case& c : cases()) {
    const sg::Sggx s = make(c);
    for (Vec3 w : kDirections) {
      const double mass = sphere_integral([&](Vec3 m) { return sg::visible_ndf(s, w, m); }, w);
      EXPECT_NEAR(mass, 1.0, kQuadTol) << name(c);
    }
  }
}

TEST(sggxDistribution, TotalFlakeAreaIsNotOne) {
  // D is normalised by projected area, not as a pdf: for surface-like S,
  // \int D dm = 2 + 2 a^2 artanh(k)/k, k = sqrt(1 - a^2) (= 4 at a = 1, -> 2 as a -> 0).
  for (double a : {0.1, 0.5, 0.9, 1.0}) {
    const double k = std::sqrt(1 - a * a);
    const double exact = 2 + 2 * a * a * (k > 0 ? std::atanh(k) / k : 1.0);
    for (Vec3 wp : {Vec3{0, 0, 1}, kTilted}) {
      const sg::Sggx s = sg::surface_like(a, wp);
      EXPECT_NEAR(sphere_integral([&](Vec3 m) { return sg::ndf(s, m); }, wp), exact, kQuadTol * exact) << a;
    }
  }
}

TEST(sggxDistribution, Eq7AsPrintedDiffersBySqrtDet) {
  // Eq. 7 prints 1/(pi alpha q^2): right for fibre-like S (sqrt det = alpha),
  // alpha times too small for surface-like S (sqrt det = alpha^2); with the
  // printed D, \int <z.m> D dm = alpha instead of sigma(z) = 1.
  for (double a : {0.1, 0.5}) {
    const sg::Sggx surf = sg::surface_like(a, {0, 0, 1}), fib = sg::fiber_like(a, {0, 0, 1});
    const Vec3 m = mcref::spherical_direction(0.4, 1.0);
    EXPECT_NEAR(sg::ndf_eq7_as_printed(fib, a, m), sg::ndf(fib, m), 1e-12 * sg::ndf(fib, m));
    EXPECT_NEAR(sg::ndf_eq7_as_printed(surf, a, m), a * sg::ndf(surf, m), 1e-12 * sg::ndf(surf, m));
    const double printed = sphere_integral(
        [&](Vec3 w) { return std::fmax(0.0, w.z) * sg::ndf_eq7_as_printed(surf, a, w); }, {0, 0, 1}, kPi / 2);
    EXPECT_NEAR(printed, a, kQuadTol);
  }
}

TEST(sggxFlakePhase, IsotropicAtAlphaOne) {
  const sg::Sggx s = sg::surface_like(1, kTilted);
  mcref::Rng rng(7);
  for (int k = 0; k < 100; ++k) {
    const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    const Vec3 wo = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    EXPECT_NEAR(sg::specular_flake_phase(s, wi, wo), 1 / (4 * kPi), 1e-14);
    // F = gamma when f0 = 1: the phase is gamma / (4 pi).
    EXPECT_NEAR(sg::specular_flake_phase_weighted(s, 0.7, 1.0, wi, wo), 0.7 / (4 * kPi), 1e-14);
  }
}

TEST(sggxFlakePhase, ReciprocityEq1) {
  // sigma(i) f_p(i->o) = sigma(o) f_p(o->i), and F is symmetric.
  mcref::Rng rng(11);
  for (const Case& c : cases()) {
    const sg::Sggx s = make(c);
    for (int k = 0; k < 20; ++k) {
      const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
      const Vec3 wo = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
      const double a = sg::projected_area(s, wi) * sg::specular_flake_phase_weighted(s, 0.8, 0.04, wi, wo);
      const double b = sg::projected_area(s, wo) * sg::specular_flake_phase_weighted(s, 0.8, 0.04, wo, wi);
      EXPECT_NEAR(a, b, 1e-12 * std::fabs(a)) << name(c);
    }
  }
}

TEST(sggxFlakePhase, NormalisationAndMeanReflectance) {
  // \int f_p dwo = 1; \int F f_p dwo = \int F(m) D_wi(m) dm (= gamma for f0 = 1).
  // Pole at -wi, where h = normalize(wi + wo) is singular (see sggx_quadrature.h).
  const double gamma = 0.8;
  for (const Case& c : cases()) {
    const sg::Sggx s = make(c);
    for (Vec3 wi : kDirections) {
      const double norm = sphere_integral([&](Vec3 wo) { return sg::specular_flake_phase(s, wi, wo); }, -wi);
      EXPECT_NEAR(norm, 1.0, kQuadTol) << name(c);
      const double white = sphere_integral(
          [&](Vec3 wo) { return sg::specular_flake_phase_weighted(s, gamma, 1.0, wi, wo); }, -wi);
      EXPECT_NEAR(white, gamma, kQuadTol) << name(c);
      for (double f0 : {0.04, 0.5}) {
        const double by_o = sphere_integral(
            [&](Vec3 wo) { return sg::specular_flake_phase_weighted(s, gamma, f0, wi, wo); }, -wi);
        const double by_m = sphere_integral(
            [&](Vec3 m) { return sg::flake_reflectance(gamma, f0, wi, m) * sg::visible_ndf(s, wi, m); }, wi);
        EXPECT_NEAR(by_o, by_m, kQuadTol) << name(c) << " f0=" << f0;
        EXPECT_LT(by_o, gamma);
      }
    }
  }
}

TEST(sggxFlakePhase, SampleReportsItsDensity) {
  const sg::Sggx s = sg::fiber_like(0.3, kTilted);
  mcref::Rng rng(3);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    const sg::PhaseSample ps = sg::sample_specular_flake_phase(s, 0.9, 0.1, wi, rng.uniform(), rng.uniform());
    ASSERT_TRUE(ps.valid);
    EXPECT_NEAR(length(ps.wo), 1.0, 1e-12);
    EXPECT_NEAR(ps.pdf, sg::specular_flake_phase(s, wi, ps.wo), 1e-10 * ps.pdf);
    const Vec3 h = normalize(wi + ps.wo);
    EXPECT_NEAR(ps.weight, sg::flake_reflectance(0.9, 0.1, wi, h), 1e-10);
    const Vec3 m = sg::sample_visible_normal(s, wi, rng.uniform(), rng.uniform());
    EXPECT_GE(dot(m, wi), 0.0);
  }
}

}  // namespace
