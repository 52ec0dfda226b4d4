// models/lambert_sphere/decay_rate.h: the dispersion function K^(0) on the
// imaginary axis and its root s0, the asymptotic decay rate of the diffuse
// radiance (what sim/spheres' depth rule uses).
#include <gtest/gtest.h>

#include <cmath>

#include "models/core/quadrature.h"
#include "models/lambert_sphere/characteristic.h"
#include "models/lambert_sphere/decay_rate.h"

namespace ls = mcref::lambert_sphere;

// Both branches (series below s = 1/2, closed form above) against Gauss-Legendre
// quadrature of 1 - 2 \int Psi^(0) / (1 - s^2 mu^2), and K(0) against Eq. 32.
TEST(lambert_sphere_DecayRate, DispersionOnTheImaginaryAxis) {
  const mcref::GaussLegendre gl(400);
  for (double c : {0.1, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(ls::dispersion_imaginary(c, 0), ls::dispersion_at_zero(0, c), 1e-15);
    for (double s : {0.1, 0.4, 0.5, 0.5000001, 0.7, 0.9}) {
      double integral = 0;
      for (int k = 0; k < static_cast<int>(gl.x.size()); ++k) {
        const double mu = 0.5 * (gl.x[k] + 1);
        integral += 0.5 * gl.w[k] * ls::characteristic_psi(0, c, mu) / (1 - s * s * mu * mu);
      }
      EXPECT_NEAR(ls::dispersion_imaginary(c, s), 1 - 2 * integral, 1e-12) << "c " << c << " s " << s;
    }
  }
}

// The root is a root, decreases with the albedo, and tends to diffusion's
// sqrt(3 (1 - c)(1 - c g)) (g = -4/9) as c -> 1; at c = 0 there is none (1).
TEST(lambert_sphere_DecayRate, RootAndItsLimits) {
  double last = 1;
  for (double c : {0.3, 0.6, 0.64, 0.8, 0.9, 0.99}) {
    const double s0 = ls::decay_rate(c);
    EXPECT_LE(s0, last) << c;
    last = s0;
    if (s0 < 1 - 1e-9) {
      EXPECT_GT(ls::dispersion_imaginary(c, s0 * (1 - 1e-9)), 0) << c;
      EXPECT_LT(ls::dispersion_imaginary(c, s0 * (1 + 1e-9)), 0) << c;
    }
  }
  EXPECT_EQ(ls::decay_rate(0), 1);
  const double c = 0.9999, diffusion = std::sqrt(3 * (1 - c) * (1 + 4 * c / 9));
  EXPECT_NEAR(ls::decay_rate(c) / diffusion, 1, 1e-3);
}
