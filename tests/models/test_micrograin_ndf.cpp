// models/micrograin: NDF (LRPB23 Eq. 16–19, vNDF paper Eq. 7–8), GGX, alpha~ (Eq. 18).
#include <gtest/gtest.h>

#include <cmath>

#include "models/core/quadrature.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/unit_space.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {

// ∫ g(m) d omega over the upper hemisphere, for an integrand peaked at the pole
// with slope scales (bx, by): for each phi, integrate in theta' with
// tan theta = tan theta' / k(phi), k^2 = cos^2 phi / bx^2 + sin^2 phi / by^2.
template <class G>
double hemisphere_integral(double bx, double by, G&& g, int phi_panels = 16, int theta_panels = 8) {
  return integrate_composite(
      [&](double phi) {
        const double k = std::hypot(std::cos(phi) / bx, std::sin(phi) / by);
        return integrate_composite(
            [&](double tp) {
              const double s = std::sin(tp), c = std::cos(tp);
              const double th = std::atan2(s, k * c);
              const double dth = k / (k * k * c * c + s * s);
              return g(spherical_direction(th, phi)) * std::sin(th) * dth;
            },
            0.0, kPi / 2, theta_panels, 16);
      },
      0.0, 2 * kPi, phi_panels, 16);
}

}  // namespace

TEST(MicrograinNdf, Eq16EqualsEq17) {
  for (double tau0 : {0.05, 0.5, 0.98})
    for (double beta : {0.2, 0.7, 1.0})
      for (double th : {0.0, 0.3, 0.8, 1.2, 1.5}) {
        const double d17 = ndf(tau0, beta, th);
        EXPECT_NEAR(ndf_eq16(tau0, beta, th), d17, 1e-12 * d17) << tau0 << " " << beta << " " << th;
      }
}

// Quadrature tolerance: the 1-D rule below converges to ~1e-14; 1e-9 leaves margin.
TEST(MicrograinNdf, IsotropicNormalisation1D) {
  for (double tau0 : {0.01, 0.5, 0.98})
    for (double beta : {0.1, 0.5, 1.0, 2.5}) {
      // theta = atan(beta tan theta'): smooth in theta'.
      const double total = 2 * kPi * integrate_composite(
          [&](double tp) {
            const double th = std::atan2(beta * std::sin(tp), std::cos(tp));
            const double dth = beta / (std::cos(tp) * std::cos(tp) + beta * beta * std::sin(tp) * std::sin(tp));
            return ndf(tau0, beta, th) * std::cos(th) * std::sin(th) * dth;
          },
          0.0, kPi / 2, 16, 16);
      EXPECT_NEAR(total, 1.0, 1e-9) << tau0 << " " << beta;
    }
}

// 2-D quadrature over (phi, theta) of D(m) cos theta_m; tolerance 1e-6 (the
// rule reaches ~1e-12 here).
TEST(MicrograinNdf, NormalisationIsotropicAndAnisotropic2D) {
  const GrainField fields[] = {{0.5, 0.5, 0.5}, {0.9, 1.0, 1.0}, {0.3, 0.25, 0.8},
                               {0.98, 1.6, 0.4}, {0.6, 3.0, 2.0}};
  for (const GrainField& f : fields) {
    const double total = hemisphere_integral(f.beta_x, f.beta_y, [&](Vec3 m) { return ndf(f, m) * m.z; });
    EXPECT_NEAR(total, 1.0, 1e-6) << f.tau0 << " " << f.beta_x << " " << f.beta_y;
  }
}

TEST(MicrograinNdf, AnisotropicFormReducesToEq17) {
  const GrainField f{0.7, 0.45, 0.45};
  for (double th : {0.0, 0.2, 0.7, 1.3, 1.55})
    for (double phi : {0.0, 1.0, 2.5, 4.0}) {
      const double d = ndf(0.7, 0.45, th);
      EXPECT_NEAR(ndf(f, spherical_direction(th, phi)), d, 1e-12 * d);
    }
}

TEST(MicrograinNdf, UnitSpaceNdfIsEq17AtBetaOne) {
  for (double th : {0.0, 0.4, 1.0, 1.5}) {
    const double d = ndf(0.6, 1.0, th);
    EXPECT_NEAR(unit_ndf(0.6, std::cos(th)), d, 1e-13 * d);
  }
}

// As tau0 -> 0 the prefactor -ln(1-tau0)(1-tau0)^s / tau0 -> 1 (Eq. 17).
TEST(MicrograinNdf, ReducesToGgxAsTau0Vanishes) {
  for (double beta : {0.2, 0.8, 1.0})
    for (double th : {0.0, 0.5, 1.0, 1.4}) {
      const double g = ggx_ndf(beta, th);
      EXPECT_NEAR(ndf(1e-9, beta, th), g, 1e-8 * g);
      EXPECT_NEAR(ndf(0.0, beta, th), g, 1e-14 * g);
      // the error is first order in tau0
      EXPECT_NEAR(ndf(1e-4, beta, th), g, 1e-4 * g);
    }
  const GrainField f{1e-9, 0.3, 0.9};
  for (double th : {0.0, 0.5, 1.0, 1.4})
    for (double phi : {0.3, 2.0}) {
      const Vec3 m = spherical_direction(th, phi);
      const double g = ggx_ndf(0.3, 0.9, m);
      EXPECT_NEAR(ndf(f, m), g, 1e-8 * g);
    }
}

TEST(MicrograinGgx, NormalisedAndAnisotropicMatchesIsotropic) {
  for (double alpha : {0.05, 0.3, 1.0}) {
    const double total = hemisphere_integral(alpha, alpha, [&](Vec3 m) { return ggx_ndf(alpha, spherical_theta(m)) * m.z; });
    EXPECT_NEAR(total, 1.0, 1e-10);
    for (double th : {0.0, 0.4, 1.2}) {
      const double d = ggx_ndf(alpha, th);
      EXPECT_NEAR(ggx_ndf(alpha, alpha, spherical_direction(th, 0.7)), d, 1e-12 * d);
      EXPECT_NEAR(d, alpha * alpha / (kPi * std::pow(std::cos(th), 4) *
                                      std::pow(alpha * alpha + std::pow(std::tan(th), 2), 2)),
                  1e-12 * d);
    }
  }
  const double ta = hemisphere_integral(0.2, 0.7, [&](Vec3 m) { return ggx_ndf(0.2, 0.7, m) * m.z; });
  EXPECT_NEAR(ta, 1.0, 1e-10);
}

TEST(MicrograinGgx, LambdaClosedForm) {
  for (double alpha : {0.1, 0.5, 1.0})
    for (double th : {0.0, 0.3, 1.0, 1.5}) {
      const double t = std::tan(th);
      EXPECT_NEAR(ggx_lambda(alpha, th), 0.5 * (-1 + std::sqrt(1 + alpha * alpha * t * t)), 1e-12);
    }
  EXPECT_EQ(smith_g1(0.0), 1.0);
  EXPECT_NEAR(smith_g1(ggx_lambda(0.5, 1.0)), 1 / (1 + ggx_lambda(0.5, 1.0)), 1e-15);
}

// Eq. 18: alpha~ is defined by D_GGX(0; alpha~) = D(0).
TEST(MicrograinNdf, EquivalentRoughnessMatchesNdfAtNormal) {
  for (double tau0 : {0.1, 0.5, 0.98})
    for (double beta : {0.3, 1.0}) {
      const double a = equivalent_roughness(tau0, beta);
      EXPECT_NEAR(ggx_ndf(a, 0.0), ndf(tau0, beta, 0.0), 1e-12 * ndf(tau0, beta, 0.0));
      EXPECT_NEAR(a, beta * std::sqrt(-tau0 / std::log(1 - tau0)), 1e-14);
    }
  EXPECT_NEAR(equivalent_roughness(1e-12, 0.4), 0.4, 1e-12);
  // LRPB23 Sec. 4.2: tau0 = 0.98 keeps alpha~_max > 0.5.
  EXPECT_GT(equivalent_roughness(0.98, 1.0), 0.5);
}

// Eq. 19 against the integral of D cos theta.
TEST(MicrograinNdf, CdfMatchesIntegral) {
  for (double tau0 : {0.2, 0.9})
    for (double beta : {0.4, 1.0})
      for (double th : {0.1, 0.4, 0.9, 1.4}) {
        const double c = 2 * kPi * integrate_composite(
            [&](double t) { return ndf(tau0, beta, t) * std::cos(t) * std::sin(t); }, 0.0, th, 64, 16);
        EXPECT_NEAR(ndf_cdf_theta(tau0, beta, th), c, 1e-11);
        const double tp = std::atan(std::tan(th) / beta);  // unit-space angle
        EXPECT_NEAR(ndf_cdf_unit_theta(tau0, tp), c, 1e-11);
      }
  EXPECT_NEAR(ndf_cdf_theta(0.5, 0.5, kPi / 2), 1.0, 1e-15);
  EXPECT_EQ(ndf_cdf_theta(0.5, 0.5, 0.0), 0.0);
}
