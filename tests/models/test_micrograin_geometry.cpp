// models/micrograin: closest-grain statistics (LRPB23 Eq. 7–10), filling factor
// (Eq. 13) and the unit-space maps (vNDF paper Sec. 3).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "chi2.h"
#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/micrograin/closest_grain.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/unit_space.h"

using namespace mcref;
using namespace mcref::micrograin;

TEST(MicrograinClosestGrain, PdfIntegratesToOneAndMatchesCdf) {
  for (double rho : {0.05, 1.0, 7.0}) {
    const double rmax = 12 / std::sqrt(kPi * rho);  // exp(-144) tail
    const double total = integrate_composite(
        [&](double r) { return closest_grain_distance_pdf(r, rho); }, 0.0, rmax, 64, 16);
    EXPECT_NEAR(total, 1.0, 1e-12) << rho;
    for (double r : {0.1, 0.5, 1.0, 2.0}) {
      const double cdf = integrate_composite(
          [&](double s) { return closest_grain_distance_pdf(s, rho); }, 0.0, r, 32, 16);
      EXPECT_NEAR(cdf, closest_grain_distance_cdf(r, rho), 1e-13) << rho << " " << r;
      // Eq. 10 is per unit area: p1(r) = 2 pi r * p1(r, phi).
      EXPECT_NEAR(closest_grain_distance_pdf(r, rho), 2 * kPi * r * closest_grain_polar_pdf(r, rho),
                  1e-14);
    }
  }
}

TEST(MicrograinClosestGrain, FiniteStatisticTendsToPoissonLimit) {
  const double rho = 2.0, r = 0.4;
  const double limit = closest_grain_distance_pdf(r, rho);
  double previous = 1e300;
  for (double n : {10.0, 100.0, 1000.0, 1e5}) {
    const double err = std::fabs(closest_grain_distance_pdf_finite(r, rho, n) - limit);
    EXPECT_LT(err, previous);
    previous = err;
  }
  EXPECT_LT(previous / limit, 1e-5);
}

TEST(MicrograinClosestGrain, CdfAtGrainRadiusIsFillingFactor) {
  const double rho = 0.3, rs = 1.1;
  EXPECT_NEAR(closest_grain_distance_cdf(rs, rho), filling_factor(rho, rs, rs), 1e-15);
}

// Explicit Poisson process: 10^5 trials, Poisson(30) centres uniform in a disc of
// area 30/rho around the origin (P(no centre) = e^-30); the nearest distance is
// binned in 20 bins of equal probability under Eq. 9 and tested by chi-square
// (alpha = 0.01; it is the only chi-square test in this file).
TEST(MicrograinClosestGrain, PoissonSimulationMatchesCdf) {
  const double rho = 1.7, mean = 30.0, radius = std::sqrt(mean / (kPi * rho));
  const int trials = 100000, bins = 20;
  std::vector<double> counts(bins, 0.0);
  Rng rng(20240611);
  for (int t = 0; t < trials; ++t) {
    const std::uint64_t n = rng.poisson(mean);
    double best = radius;
    for (std::uint64_t k = 0; k < n; ++k) best = std::fmin(best, radius * std::sqrt(rng.uniform()));
    const double u = closest_grain_distance_cdf(best, rho);
    counts[std::min(bins - 1, static_cast<int>(u * bins))] += 1;
  }
  double stat = 0;
  const double e = static_cast<double>(trials) / bins;
  for (double c : counts) stat += (c - e) * (c - e) / e;
  EXPECT_GT(test::chi2_survival(stat, bins - 1), 0.01) << "chi2 = " << stat;
}

TEST(MicrograinGrainField, FillingFactorAndDensityRoundTrip) {
  const double rx = 0.7, ry = 1.9;
  for (double tau0 : {1e-6, 0.2, 0.5, 0.98}) {
    const double rho = density_from_filling_factor(tau0, rx, ry);
    EXPECT_NEAR(filling_factor(rho, rx, ry), tau0, 1e-15);
    EXPECT_NEAR(unit_density(tau0), rho * rx * ry, 1e-14 * rho * rx * ry);
    EXPECT_NEAR(1 - std::exp(-kPi * unit_density(tau0)), tau0, 1e-15);
  }
  const GrainField f = isotropic_field(0.3, 0.6);
  EXPECT_EQ(f.beta_x, 0.6);
  EXPECT_EQ(f.beta_y, 0.6);
}

namespace {
void expect_vec_near(Vec3 a, Vec3 b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}
}  // namespace

// A real half-ellipsoid with semi-axes r_x, r_y, c: its unit-space image is the
// unit hemisphere, the unit-space normal at a point is the point itself, and
// the real normal is the gradient of (x/r_x)^2 + (y/r_y)^2 + (z/c)^2.
TEST(MicrograinUnitSpace, NormalsAndDirectionsFollowTheEllipsoid) {
  const double rx = 2.0, ry = 0.5, c = 0.8;
  const GrainField f{0.4, c / rx, c / ry};
  Rng rng(3);
  for (int k = 0; k < 200; ++k) {
    const double u = rng.uniform(), v = rng.uniform();
    const Vec3 pu = spherical_direction(std::acos(u), 2 * kPi * v);  // unit-space point
    const Vec3 p{rx * pu.x, ry * pu.y, c * pu.z};                    // real point
    const Vec3 m = normalize(Vec3{p.x / (rx * rx), p.y / (ry * ry), p.z / (c * c)});
    expect_vec_near(to_unit_normal(f, m), pu, 1e-12);
    expect_vec_near(from_unit_normal(f, pu), m, 1e-12);
    EXPECT_NEAR(unit_height(f, m), pu.z, 1e-12);
    // Direction between two real points <-> unit-space difference.
    const Vec3 qu = spherical_direction(std::acos(rng.uniform()), 2 * kPi * rng.uniform());
    const Vec3 q{rx * qu.x, ry * qu.y, c * qu.z};
    expect_vec_near(to_unit_direction(f, normalize(q - p)), normalize(qu - pu), 1e-12);
    expect_vec_near(from_unit_direction(f, normalize(qu - pu)), normalize(q - p), 1e-12);
    // Normal map preserves orthogonality with tangent directions.
    const Vec3 t = normalize(cross(m, Vec3{0.3, -0.2, 0.9}));
    EXPECT_NEAR(dot(to_unit_normal(f, m), to_unit_direction(f, t)), 0.0, 1e-12);
  }
}

// The normal map is a bijection of the upper hemisphere, so its Jacobian
// d omega'/d omega integrates to 2 pi; a small cap's image area matches too.
TEST(MicrograinUnitSpace, NormalJacobianIntegratesToHemisphere) {
  for (const GrainField& f : {GrainField{0.5, 0.3, 0.3}, GrainField{0.5, 0.4, 1.7}}) {
    // Substitution tan theta = tan theta' / k(phi), k^2 = cos^2/bx^2 + sin^2/by^2
    // resolves the peak of the Jacobian.
    const double total = integrate_composite(
        [&](double phi) {
          const double k = std::hypot(std::cos(phi) / f.beta_x, std::sin(phi) / f.beta_y);
          return integrate_composite(
              [&](double tp) {
                const double th = std::atan2(std::sin(tp), k * std::cos(tp));
                const double dth = k / (k * k * std::cos(tp) * std::cos(tp) + std::sin(tp) * std::sin(tp));
                return unit_normal_jacobian(f, spherical_direction(th, phi)) * std::sin(th) * dth;
              },
              0.0, kPi / 2, 8, 16);
        },
        0.0, 2 * kPi, 16, 16);
    EXPECT_NEAR(total, 2 * kPi, 1e-9);
  }
}

TEST(MicrograinUnitSpace, IsotropicUnitFieldIsIdentity) {
  const GrainField f{0.5, 1.0, 1.0};
  const Vec3 d = normalize(Vec3{0.3, -0.4, 0.8});
  expect_vec_near(to_unit_direction(f, d), d, 1e-15);
  expect_vec_near(to_unit_normal(f, d), d, 1e-15);
  EXPECT_NEAR(unit_normal_jacobian(f, d), 1.0, 1e-15);
}
