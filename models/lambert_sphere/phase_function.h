#pragma once
// The Lambertian-sphere phase function (d'Eon 2021, Sec. 2).
//
// mu is the cosine between the incoming PROPAGATION direction and the outgoing
// direction (mu = -1: straight back toward the source). The phase function is
// normalised per steradian: \int_{4pi} p dOmega = 2 pi \int_{-1}^{1} p(mu) dmu = 1.
#include <vector>

namespace mcref::lambert_sphere {

// Eq. 1: p(mu) = 2 (sqrt(1 - mu^2) - mu acos(mu)) / (3 pi^2). Mean cosine g = -4/9.
double phase_function(double mu);

// Mean cosine 2 pi \int mu p(mu) dmu = -4/9 (closed form).
inline constexpr double kMeanCosine = -4.0 / 9.0;

// Eq. 3: A_k = 2 pi (2k + 1) \int_{-1}^{1} p(mu) P_k(mu) dmu, so that
// p = (1/4pi) sum_k A_k P_k (Eq. 2). By 64-point Gauss-Legendre in theta = acos mu,
// where the integrand 2 (sin t - t cos t) P_k(cos t) sin t / (3 pi^2) is entire:
// accurate to ~1e-15 for k <= 30.
double legendre_coefficient(int k);

// Eq. 4 as published: A_0..A_6 = 1, -4/3, 5/16, 0, 1/64, 0, 13/4096.
// Throws std::out_of_range for k outside [0, 6].
double published_legendre_coefficient(int k);

// Legendre polynomial P_k(x) by the three-term recurrence.
double legendre_polynomial(int k, double x);

// Eq. 7-8 divided by 4 pi c: the three-term truncation
// p_3(mu) = (1/4pi) (1 + A_1 P_1(mu) + A_2 P_2(mu)) = (1/4pi) (1 - 4mu/3 + 5 P_2(mu)/16).
// (Eq. 7 writes c p = w_0 + w_1 P_1 + w_2 P_2 in Chandrasekhar's normalisation,
// mean 1 over the sphere instead of 1/(4pi), with w_0 = c, w_1 = -4c/3, w_2 = 5c/16.)
double phase_function_three_term(double mu);

}  // namespace mcref::lambert_sphere
