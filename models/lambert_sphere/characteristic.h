#pragma once
// Characteristic functions Psi^(m) and dispersion functions K^(m) of the three
// pseudo-problems of the three-term half-space (d'Eon 2021, Sec. 3.1), m = 0, 1, 2
// the Fourier order; c is the particle (single-scattering) albedo in [0, 1].
#include <array>

namespace mcref::lambert_sphere {

// Psi^(m)(mu) = p0 + p2 mu^2 + p4 mu^4 (Eq. 13-15), coefficients in mu^2.
struct PsiPolynomial {
  std::array<double, 3> coef{};  // p0, p2, p4
  double operator()(double mu) const;
  // \int_0^1 mu^(2n) Psi(mu) dmu
  double even_moment(int n) const;
};
// Eq. 13 (m = 0), Eq. 14 (m = 1), Eq. 15 (m = 2). Throws std::out_of_range for other m.
PsiPolynomial characteristic_polynomial(int m, double c);
double characteristic_psi(int m, double c, double mu);

// K^(m)(0) = 1 - 2 \int_0^1 Psi^(m): m = 0 is Eq. 32, (c-16)(c-1)(4c+9)/144;
// m = 1: 1 + c (55 - 4c)/144; m = 2: 1 - c/16.
double dispersion_at_zero(int m, double c);

// Eq. 18-20 exactly as printed. Loses accuracy as t -> 0 (the bracket cancels
// to O(t^5): relative error ~1e-16 / t^4); undefined at t = 0.
double dispersion_published(int m, double c, double t);

// K^(m)(t) for all t >= 0: Eq. 18-20 for t >= 1/2, and below it the series
// K(0) + 2 sum_{n>=1} (-1)^(n+1) t^(2n) \int mu^(2n) Psi (40 terms, < 1e-24).
double dispersion(int m, double c, double t);

}  // namespace mcref::lambert_sphere
