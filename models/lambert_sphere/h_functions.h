#pragma once
// H-functions of the three-term Lambertian-sphere half-space (d'Eon 2021, Sec. 3.1)
// and the published fits H^(1) (Eq. 23-25) and H^(0) (Eq. 31-32).
// m = Fourier order 0, 1, 2; c = particle albedo in [0, 1]; mu in [0, 1].
#include "models/radiative_transfer/h_function.h"

namespace mcref::lambert_sphere {

// Exact H^(m)(mu) by Fock's integral (Eq. 16) with the closed-form K^(m)
// (Eq. 18-20, series near t = 0); ~0.1 ms per call.
double h_exact(int m, double c, double mu);

// Exact H^(m) tabulated once per (m, c), ~1 us per evaluation afterwards.
radiative_transfer::HTable h_table(int m, double c);

// Eq. 24: H^(1) at c = 1, fit exp(-0.0894878 mu^(-1.12831 mu^3 + 1.85728 mu^2 - 1.07879 mu + 0.459442)).
// As published it gives 0.9144 at mu = 1 (see tests for its error against h_exact).
double h1_fit_conservative(double mu);
// Eq. 25: H^(1)(1) ~ exp(0.0242851 c^2 - 0.144839 c).
double h1_fit_at_one(double c);
// Eq. 23: H^(1)(mu) ~ H^(1)(1) H^(1)_{c=1}(mu), Eq. 24 x Eq. 25.
double h1_fit(double c, double mu);

// NOT PUBLISHED: a reading of Eq. 23-25 that fits. As printed, Eq. 23 cannot be
// right (it gives H^(1)(0) = H^(1)(1) != 1, and Eq. 24 is 0.914 at mu = 1 where it
// should be 1 or H^(1)_{c=1}(1) = 0.886); the log-separable form
//   H^(1)(mu) ~ H^(1)(1)^(mu^e(mu)),  e(mu) = -1.12831 mu^3 + 1.85728 mu^2 - 1.07879 mu + 0.459442,
// with H^(1)(1) from Eq. 25, is within 0.37 % of the exact H^(1) for all c
// (measured, tests), matching the paper's "0.5 %" claim.
double h1_fit_log_separable(double c, double mu);

// Eq. 32: H^(0)(inf) = 1/sqrt(K^(0)(0)) = 12 / sqrt((c-16)(c-1)(4c+9)); +inf at c = 1.
double h0_at_infinity(double c);
// Eq. 31: H^(0)(mu) ~ (1 + a mu^d) / (1 + a mu^d / H^(0)(inf)), with a, d of s = sqrt(1-c).
double h0_fit(double c, double mu);

}  // namespace mcref::lambert_sphere
