// models/micrograin: projected cap area sigma(i, h) (vNDF paper Eq. 5), the
// height-dependent filling factor tau(i, h) (Eq. 4/10) and G_dist (Eq. 3/9).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "models/micrograin/height_masking.h"
#include "models/micrograin/projected_area.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"
#include "tests/models/micrograin_union_area_reference.h"

using namespace mcref;
using namespace mcref::micrograin;

// The closed form (LilTracer's, evaluated as the shadow set's arc sector) against
// the independent union-of-discs quadrature,
// on a grid of incidence angles and heights (including the no-shadow region).
TEST(MicrograinProjectedArea, ClosedFormMatchesNumericalArea) {
  for (double th_deg : {0.0, 5.0, 20.0, 45.0, 60.0, 75.0, 85.0, 89.0})
    for (double h : {0.0, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 1.0}) {
      const double th = deg_to_rad(th_deg);
      const double closed = projected_cap_area(th, h);
      const double numeric = projected_cap_area_numeric(th, h);
      EXPECT_NEAR(closed, numeric, 1e-10 * std::fmax(1.0, closed)) << th_deg << " deg, h " << h;
      // numeric self-convergence (panels x4)
      EXPECT_NEAR(numeric, projected_cap_area_numeric(th, h, 256), 1e-11 * std::fmax(1.0, closed));
    }
}

TEST(MicrograinProjectedArea, SpecialValues) {
  for (double th : {0.0, 0.3, 0.9, 1.3, 1.55}) {
    // h = 0: half disc plus half ellipse.
    EXPECT_NEAR(projected_cap_area(th, 0.0), 0.5 * kPi * (1 + 1 / std::cos(th)), 1e-12 / std::cos(th));
    for (double h : {0.0, 0.2, 0.6, 0.95}) {
      if (h >= std::sin(th)) {
        EXPECT_EQ(cap_shadow_area(th, h), 0.0);
      } else {
        EXPECT_GT(cap_shadow_area(th, h), 0.0);
      }
      EXPECT_NEAR(projected_cap_area(th, h) - cap_shadow_area(th, h), kPi * (1 - h * h), 1e-14);
    }
    EXPECT_NEAR(projected_cap_area(th, 1.0), 0.0, 1e-15);
  }
  EXPECT_NEAR(cap_cross_section(0.5), 0.75 * kPi, 1e-15);
  // shadow decreases with height, vanishes continuously at h = sin theta
  const double th = 1.0;
  double prev = 1e300;
  for (double h = 0; h < std::sin(th); h += 0.01) {
    const double s = cap_shadow_area(th, h);
    EXPECT_LT(s, prev);
    prev = s;
  }
  EXPECT_LT(cap_shadow_area(th, std::sin(th) - 1e-6), 1e-7);
  EXPECT_NEAR(projected_cap_area(Vec3{std::sin(th), 0, std::cos(th)}, 0.3), projected_cap_area(th, 0.3), 1e-14);
}

// tau(i, 0) must equal tau+ of LRPB23 Eq. 22 analytically:
// rho' sigma(i, 0) = -ln(1-tau0)/2 (1 + gamma_beta/cos theta).
TEST(MicrograinHeightFilling, AtHeightZeroEqualsTauPlus) {
  const GrainField fields[] = {{0.5, 1.0, 1.0}, {0.2, 0.3, 0.3}, {0.9, 0.7, 0.7}, {0.7, 2.0, 2.0},
                               {0.6, 0.4, 1.3}};
  for (const GrainField& f : fields)
    for (double th : {0.0, 0.4, 1.0, 1.5})
      for (double phi : {0.0, 1.1, 3.0}) {
        const Vec3 i = spherical_direction(th, phi);
        EXPECT_NEAR(filling_factor_at_height(f, i, 0.0), tau_plus(f, i), 1e-13);
        if (f.beta_x == f.beta_y) {
          EXPECT_NEAR(filling_factor_at_height(f, i, 0.0), tau_plus(f.tau0, f.beta_x, th), 1e-13);
        }
      }
}

TEST(MicrograinHeightFilling, NormalIncidenceAndLimits) {
  const GrainField f{0.4, 0.6, 0.9};
  const Vec3 n{0, 0, 1};
  EXPECT_NEAR(filling_factor_at_height(f, n, 0.0), 0.4, 1e-15);
  EXPECT_NEAR(filling_factor_at_height(f, n, 1.0), 0.0, 1e-15);
  // at normal incidence tau(n, cos theta)/tau0 is the NDF CDF (vNDF Eq. 14)
  EXPECT_NEAR(filling_factor_at_height(f, n, 0.6), 1 - std::pow(0.6, 1 - 0.36), 1e-15);
}

TEST(MicrograinDistantMasking, Properties) {
  const GrainField f{0.7, 0.5, 1.2};
  const Vec3 n{0, 0, 1};
  for (double h : {0.0, 0.5, 1.0}) EXPECT_EQ(distant_masking(f, n, h), 1.0);
  for (double th : {0.3, 1.0, 1.4})
    for (double phi : {0.0, 2.0}) {
      const Vec3 i = spherical_direction(th, phi);
      const double theta_u = spherical_theta(to_unit_direction(f, i));
      double prev = 0;
      for (double h = 0; h <= 1.0; h += 0.05) {
        const double g = distant_masking(f, i, h);
        EXPECT_GE(g, prev);  // higher points are less masked
        EXPECT_LE(g, 1.0);
        // definition: exp(-rho' sigma(i', h)) / exp(-rho' sigma(n, h))
        const double rho = unit_density(f.tau0);
        EXPECT_NEAR(g, std::exp(-rho * projected_cap_area(theta_u, h)) / std::exp(-rho * kPi * (1 - h * h)),
                    1e-13);
        if (h >= std::sin(theta_u)) {
          EXPECT_EQ(g, 1.0);
        }
        prev = g;
      }
    }
}

// Where the arc beyond the disc vanishes (h -> sin theta), against the adaptive
// integral of the radius (micrograin_union_area_reference.h, i == o, 1e-14 of the
// scale, 4096-point crossing grid): 1e-9 relative and 1e-15 absolute. LilTracer's
// acos form lost up to 8e-9 there (2 % at 89.99 deg, 1 - h / sin theta = 1e-7).
TEST(MicrograinProjectedArea, ShadowAccurateWhereTheArcVanishes) {
  for (double th_deg : {30.0, 60.0, 85.0, 89.99})
    for (int k = 4; k <= 14; ++k) {
      const double th = deg_to_rad(th_deg), h = std::sin(th) * (1 - std::pow(10.0, -k));
      const Vec3 d = spherical_direction(th, 0.3);
      const double ref = test::union_area_adaptive(d, d, h, 1e-14, 4096);
      EXPECT_NEAR(cap_shadow_area(d, h), ref, 1e-9 * std::fabs(ref) + 1e-15) << th_deg << " deg, k " << k;
    }
}

// Near grazing (theta = pi/2 - delta, delta = 1e-3 ... 1e-9; the area grows as
// 1 / cos theta): both overloads against LilTracer's form (projected_area.h)
// evaluated in long double (64-bit mantissa) at the same double inputs, 1e-12
// relative. theta's overload takes cos theta of its (double) argument, exact to an
// ulp; what it cannot know is the rounding of pi/2 - delta to a double, up to 1e-16
// absolute, i.e. ~1e-16 / delta relative in cos theta: callers with the direction's
// z use the Vec3 overload (all of models/micrograin does).
TEST(MicrograinProjectedArea, ShadowAccurateNearGrazing) {
  auto reference = [](long double s, long double c, long double h) {
    // (s, c) normalised, as ShadowSet does: near h = sin theta the area is
    // ill-conditioned in s^2 + c^2 - 1 (1e-16 of it moves it by 1e-11 at h = 0.999).
    const long double n = std::sqrt(s * s + c * c);
    s /= n;
    c /= n;
    const long double sm = std::sqrt(1 - h * h), cos_phiq = -h * c / (s * sm);
    const long double qx = sm * cos_phiq, qy = sm * std::sqrt(1 - cos_phiq * cos_phiq), ex = h * s / c;
    const long double sigma_e = std::acos(std::clamp(-(qx - ex) * c, 0.0L, 1.0L)) / c;
    return sigma_e - std::fabs(ex * qy) - (kPi - std::acos(cos_phiq)) * sm * sm;
  };
  for (int k = 3; k <= 9; ++k)
    for (double h : {0.0, 0.3, 0.9, 0.999}) {
      const double th = kPi / 2 - std::pow(10.0, -k);
      const Vec3 d = spherical_direction(th, 0);
      const long double ref_theta = reference(std::sin(static_cast<long double>(th)), std::cos(static_cast<long double>(th)), h);
      const long double ref_d = reference(d.x, d.z, h);
      EXPECT_NEAR(cap_shadow_area(th, h) / ref_theta, 1.0, 1e-12) << "theta = pi/2 - 1e-" << k << ", h " << h;
      EXPECT_NEAR(cap_shadow_area(d, h) / ref_d, 1.0, 1e-12) << "theta = pi/2 - 1e-" << k << ", h " << h;
    }
}
