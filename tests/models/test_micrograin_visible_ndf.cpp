// models/micrograin: visible NDF with height-correlated masking (vNDF paper
// Eq. 6, 11–13), its marginal CDF (Eq. 19) and conditional CDF (Eq. 22).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_ndf.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {

// ∫ D_v(i, m) d omega_m over real normals m whose unit-space polar angle is at
// most theta_max. Outer: real azimuth phi. Inner: the unit-space polar angle
// theta' (tan theta_m = tan theta' / k(phi), k^2 = cos^2/bx^2 + sin^2/by^2),
// split where D_v has kinks: the shadow edge h = cos theta' = sin theta_i' and
// the visibility edge i.m = 0.
double integrate_visible_ndf(const GrainField& f, Vec3 i, double theta_max = kPi / 2) {
  const Vec3 iu = to_unit_direction(f, i);
  const double shadow_edge = kPi / 2 - spherical_theta(iu);
  auto inner = [&](double phi) {
    const double k = std::hypot(std::cos(phi) / f.beta_x, std::sin(phi) / f.beta_y);
    auto g = [&](double tp) {
      const double s = std::sin(tp), c = std::cos(tp);
      const double th = std::atan2(s, k * c);
      const double dth = k / (k * k * c * c + s * s);
      return visible_ndf(f, i, spherical_direction(th, phi)) * std::sin(th) * dth;
    };
    std::vector<double> cuts{0.0, theta_max};
    if (shadow_edge < theta_max) cuts.push_back(shadow_edge);
    const double ip = i.x * std::cos(phi) + i.y * std::sin(phi);  // i.m = sin th ip + cos th i.z
    if (ip < 0) {
      const double th0 = std::atan2(i.z, -ip);               // real angle where i.m = 0
      const double tp0 = std::atan2(k * std::sin(th0), std::cos(th0));  // its unit-space angle
      if (tp0 < theta_max) cuts.push_back(tp0);
    }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c)
      sum += integrate_composite(g, cuts[c], cuts[c + 1], 2, 16);
    return sum;
  };
  return integrate_composite(inner, 0.0, 2 * kPi, 64, 16);
}

const GrainField kFields[] = {{0.5, 1.0, 1.0}, {0.9, 0.5, 0.5}, {0.3, 2.0, 2.0}, {0.6, 0.4, 1.3},
                              {0.95, 3.0, 0.8}, {0.05, 0.25, 0.25}};

}  // namespace

// Normalisation over grain hits: tolerance 1e-6, from the quadrature error of
// the kinked azimuthal integrand (the rule reaches ~1e-9 here).
TEST(MicrograinVisibleNdf, IntegratesToOne) {
  for (const GrainField& f : kFields)
    for (double th_deg : {0.0, 30.0, 60.0, 80.0, 88.0})
      for (double phi : {0.4, 2.0}) {
        const Vec3 i = spherical_direction(deg_to_rad(th_deg), phi);
        EXPECT_NEAR(integrate_visible_ndf(f, i), 1.0, 1e-6)
            << "tau0 " << f.tau0 << " beta " << f.beta_x << "," << f.beta_y << " theta_i " << th_deg;
      }
}

// beta = 1: the real-space form is the unit-space Eq. 13; otherwise they are
// related by the normal-map Jacobian det(M)/|M^T m|^3 (Eq. 11–12).
TEST(MicrograinVisibleNdf, MatchesUnitSpaceEq13) {
  Rng rng(5);
  for (const GrainField& f : kFields)
    for (int k = 0; k < 300; ++k) {
      const Vec3 i = spherical_direction(std::acos(rng.uniform()), 2 * kPi * rng.uniform());
      const Vec3 m = spherical_direction(std::acos(rng.uniform()), 2 * kPi * rng.uniform());
      const double dv = visible_ndf(f, i, m);
      const double du = visible_ndf_unit(f.tau0, to_unit_direction(f, i), to_unit_normal(f, m));
      if (f.beta_x == 1.0 && f.beta_y == 1.0) {
        EXPECT_NEAR(dv, du, 1e-12 * std::fmax(1.0, du));
      }
      EXPECT_NEAR(dv, unit_normal_jacobian(f, m) * du, 1e-11 * std::fmax(1.0, dv));
    }
  // invisible or back-facing normals have zero density
  const GrainField f{0.5, 1.0, 1.0};
  EXPECT_EQ(visible_ndf(f, Vec3{0, 0, 1}, Vec3{0, 0, -1}), 0.0);
  EXPECT_EQ(visible_ndf(f, spherical_direction(1.2, 0.0), spherical_direction(1.2, kPi)), 0.0);
}

// Eq. 19 against the numerical integral of D_v over theta' <= theta.
TEST(MicrograinVisibleNdf, MarginalCdfMatchesIntegral) {
  for (const GrainField& f : kFields)
    for (double th_deg : {20.0, 70.0, 85.0}) {
      const Vec3 i = spherical_direction(deg_to_rad(th_deg), 0.9);
      for (double tm_deg : {10.0, 30.0, 50.0, 70.0, 85.0}) {
        const double tm = deg_to_rad(tm_deg);
        EXPECT_NEAR(visible_ndf_marginal_cdf(f, i, tm), integrate_visible_ndf(f, i, tm), 1e-6)
            << f.tau0 << " " << f.beta_x << "," << f.beta_y << " " << th_deg << " " << tm_deg;
      }
      EXPECT_NEAR(visible_ndf_marginal_cdf(f, i, 0.0), 0.0, 1e-15);
      EXPECT_NEAR(visible_ndf_marginal_cdf(f, i, kPi / 2), 1.0, 1e-12);
    }
}

// Eq. 22/26 (with phi_q) against numerical integration of Eq. 13 on a ring.
TEST(MicrograinVisibleNdf, ConditionalCdfMatchesRingIntegral) {
  const double tau0 = 0.7;
  for (double ti : {0.3, 0.9, 1.4})
    for (double tm : {0.2, 0.8, 1.3}) {
      const Vec3 iu = spherical_direction(ti, 0.0);
      const double phi_q = visible_azimuth_bound(ti, tm);
      auto ring = [&](double p) { return visible_ndf_unit(tau0, iu, spherical_direction(tm, p)); };
      const double total = integrate_composite(ring, -phi_q, phi_q, 16, 16);
      EXPECT_NEAR(visible_ndf_conditional_cdf(ti, tm, phi_q), 1.0, 1e-14);
      EXPECT_NEAR(visible_ndf_conditional_cdf(ti, tm, -phi_q), 0.0, 1e-14);
      for (double frac : {-0.8, -0.3, 0.0, 0.5, 0.95}) {
        const double p = frac * phi_q;
        const double partial = integrate_composite(ring, -phi_q, p, 16, 16);
        EXPECT_NEAR(visible_ndf_conditional_cdf(ti, tm, p), partial / total, 1e-12);
        EXPECT_NEAR(visible_ndf_conditional_pdf(ti, tm, p), ring(p) / total, 1e-12 * std::fmax(1.0, ring(p) / total));
      }
      // phi_q bounds the visible ring: i'.m' = 0 there (or the whole ring is visible).
      if (phi_q < kPi) {
        EXPECT_NEAR(dot(iu, spherical_direction(tm, phi_q)), 0.0, 1e-14);
      } else {
        EXPECT_GT(dot(iu, spherical_direction(tm, kPi)), -1e-15);
      }
    }
}
