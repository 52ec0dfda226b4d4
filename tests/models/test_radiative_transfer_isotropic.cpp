// models/radiative_transfer: isotropic half-space BRDFs (single scattering and all orders).
#include <gtest/gtest.h>

#include <cmath>

#include "models/core/quadrature.h"
#include "models/core/vec.h"
#include "models/radiative_transfer/isotropic.h"

namespace rt = mcref::radiative_transfer;
using mcref::kPi;

TEST(radiative_transfer_Isotropic, SingleScatteringFormula) {
  EXPECT_DOUBLE_EQ(rt::single_scattering_brdf_isotropic(0.8, 0.3, 0.5), 0.8 / (4 * kPi * 0.8));
  EXPECT_EQ(rt::single_scattering_brdf_isotropic(0.8, 0.0, 0.5), 0.0);
  EXPECT_EQ(rt::brdf_isotropic(0.8, 0.3, -0.5), 0.0);
}

// All orders = albedo H H / (4 pi (mu_i + mu_o)); the class (tables) and the free
// functions (Fock per call) agree to the table accuracy (1e-12 in H).
TEST(radiative_transfer_Isotropic, ClassAgreesWithFreeFunctions) {
  for (double w : {0.3, 0.95, 1.0}) {
    const rt::IsotropicHalfSpace m(w);
    for (double a : {0.05, 0.4, 1.0})
      for (double b : {0.01, 0.7}) {
        const double f = rt::brdf_isotropic(w, a, b);
        EXPECT_NEAR(m.brdf(a, b), f, 1e-11 * f);
        EXPECT_DOUBLE_EQ(m.brdf(a, b), m.brdf(b, a));  // reciprocity
        EXPECT_GT(m.multiple_scattering(a, b), 0.0);
        EXPECT_NEAR(f, w * rt::h_isotropic(w, a) * rt::h_isotropic(w, b) / (4 * kPi * (a + b)), 1e-15);
      }
  }
}

// Energy: 2 pi \int f mu_o dmu_o = 1 - H(mu_i) sqrt(1 - w) (= 1 at w = 1).
// Graded Gauss quadrature in mu_o (integrand ~ mu_o log mu_o near 0): 1e-10.
TEST(radiative_transfer_Isotropic, DirectionalAlbedo) {
  for (double w : {0.5, 0.9, 1.0}) {
    const rt::IsotropicHalfSpace m(w);
    for (double mu_i : {0.02, 0.3, 0.8, 1.0}) {
      double s = 0;
      for (int j = 0; j < 30; ++j)
        s += mcref::integrate_composite([&](double mu) { return m.brdf(mu_i, mu) * mu; }, std::ldexp(1.0, -(j + 1)),
                                        std::ldexp(1.0, -j), 1, 16);
      const double albedo = 2 * kPi * s;
      EXPECT_NEAR(albedo, m.directional_albedo(mu_i), 1e-10) << "w " << w << " mu_i " << mu_i;
      if (w == 1.0) {
        EXPECT_NEAR(albedo, 1.0, 1e-10);
      }
    }
  }
}

// As the albedo -> 0 all orders reduce to single scattering: f / f1 = H H = 1 + O(w).
TEST(radiative_transfer_Isotropic, SmallAlbedoLimit) {
  const double w = 1e-6;
  EXPECT_NEAR(rt::brdf_isotropic(w, 0.4, 0.6) / rt::single_scattering_brdf_isotropic(w, 0.4, 0.6), 1.0, 1e-5);
}
