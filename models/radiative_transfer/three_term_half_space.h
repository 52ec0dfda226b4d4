#pragma once
// Exact azimuthal Fourier modes of the BRDF of a semi-infinite, homogeneous
// medium with a three-term phase function, all orders of scattering, solved
// numerically (no fitted constants). Reference for d'Eon 2021 Eq. 22 and 30,
// which give the same modes in closed form with fitted constants.
//
// Phase function (per steradian, mu = cosine between incoming propagation and
// outgoing direction):  p(mu) = (1/4pi) (1 + a1 P_1(mu) + a2 P_2(mu)),
// albedo c, extinction 1. (Horak & Chandrasekhar's w_k = c a_k, d'Eon Eq. 7-8.)
//
// BRDF: f_r(mu_i, mu_o, phi) = sum_m f^(m)(mu_i, mu_o) cos(m phi), sr^-1 without
// the cosine; omega_i, omega_o both point away from the surface and
// phi = phi_o - phi_i, phi = 0 back toward the light (DESIGN.md). Only m <= 2
// are non-zero for a three-term phase function.
//
// Method: Ambartsumian's invariance principle (adding a thin layer on top of
// the half-space changes nothing), per Fourier order m:
//   (mu_i + mu_o) f = c [ p-(mu_i, mu_o) + g mu_o \int p+(mu_i, x) f(x, mu_o) dx
//                        + g mu_i \int f(mu_i, x) p+(x, mu_o) dx
//                        + g^2 mu_i mu_o \int\int f(mu_i, x) p-(x, y) f(y, mu_o) dx dy ],
// with g = 2 pi (m = 0) or pi (m >= 1), p+- the m-th Fourier coefficients of
// p(+-(a b + sqrt(1-a^2) sqrt(1-b^2) cos phi)). The kernels are separable,
// p(a, b) = u(a)^T M u(b), so the unknowns are the R <= 3 moments
// X_r(mu) = \int f(mu, x) u_r(x) dx at Nystrom nodes (graded toward mu = 0,
// cos-substituted near mu = 1), found by fixed-point iteration (successive
// orders of scattering, accelerated by Anderson(1) mixing); any (mu_i, mu_o) is
// then evaluated by the Nystrom formula. 272 nodes; 10-100 ms per solve.
// Measured against Chandrasekhar's isotropic c H H / (4 pi (mu_i + mu_o)):
// relative error < 1e-12 for c <= 0.99, 2e-11 at c = 0.999 (tests).
#include <array>
#include <vector>

namespace mcref::radiative_transfer {

class ThreeTermHalfSpace {
 public:
  struct Options {
    double tolerance = 1e-13;    // on max |X_new - X_old| / max |X|
    int max_iterations = 20000;
    bool anderson = true;        // Anderson(1) mixing; false: plain successive orders
  };
  // Throws std::invalid_argument for order outside {0, 1, 2}, albedo outside
  // [0, 1] (m = 1, 2) or [0, 1) (m = 0: the conservative case converges to only
  // ~1e-6; use c = 0.9999, accurate to 1e-11), or no convergence.
  ThreeTermHalfSpace(double albedo, double a1, double a2, int order, Options options);
  ThreeTermHalfSpace(double albedo, double a1, double a2, int order)
      : ThreeTermHalfSpace(albedo, a1, a2, order, Options{}) {}

  // f^(m)(mu_i, mu_o), all orders of scattering; 0 unless mu_i, mu_o > 0.
  double mode(double mu_i, double mu_o) const;
  // Its single-scattering part c p-_m(mu_i, mu_o) / (mu_i + mu_o).
  double single_scattering_mode(double mu_i, double mu_o) const;
  int order() const { return order_; }
  int iterations() const { return iterations_; }

 private:
  using Vec = std::array<double, 3>;
  Vec basis(double mu) const;                       // u(mu)
  double kernel(const Vec& ua, const Vec& ub, int sign) const;  // u^T M(sign) u
  Vec apply(const Vec& v, int sign) const;          // M(sign) v
  Vec moments_at(double mu) const;                  // X(mu) by the Nystrom formula
  double mode_from(double mu_i, const Vec& ui, const Vec& xi, double mu_o, const Vec& uo,
                   const Vec& xo) const;

  double c_, a1_, a2_, gamma_;
  int order_, rank_, iterations_ = 0;
  std::array<std::array<double, 3>, 3> m_plus_{}, m_minus_{};
  std::vector<double> mu_, w_;
  std::vector<Vec> u_, x_;
};

}  // namespace mcref::radiative_transfer
