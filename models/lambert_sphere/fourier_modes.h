#pragma once
// Azimuthal Fourier modes of the Lambertian-sphere half-space BRDF (d'Eon 2021, Sec. 3).
//
// f_r(mu_i, mu_o, phi) = f^(0) + f^(1) cos(phi) + f^(2) cos(2 phi)   (Eq. 9)
// sr^-1 WITHOUT the cosine; mu_i, mu_o cosines of omega_i, omega_o, both
// pointing away from the surface; phi = phi_o - phi_i the relative azimuth.
//
// phi convention: phi = 0 is back toward the light (omega_o on the side of
// omega_i, retro-reflection), phi = pi the mirror side, as in DESIGN.md. d'Eon's
// phi is the same: the single-scattering cos(phi) coefficient of the
// back-scattering phase function is positive in Eq. 22/28, which is only true
// with phi = 0 at retro-reflection. (Horak & Chandrasekhar's azimuth, measured
// from the incident propagation direction, is phi + pi.)
//
// FINDING (tests/models/test_lambert_sphere_fourier.cpp): Eq. 22 is half the
// cos(phi) mode of the three-term half-space. The exact mode, solved without
// fits (radiative_transfer::ThreeTermHalfSpace), equals 2 x Eq. 22 with exact
// H^(1) and l, m to 1e-9 for every c; the true single-scattering cos(phi)
// coefficient of Eq. 10 with the three-term phase function is the 192 pi form,
// twice Eq. 28's 384 pi term. Eq. 30 and Eq. 38 (zeroth mode) are exact.
#include "models/lambert_sphere/mode_constants.h"

namespace mcref::lambert_sphere {

// S = sqrt(1 - mu_i^2) sqrt(1 - mu_o^2).
double sine_product(double mu_i, double mu_o);

// Eq. 22 as published: c H1(mu_i) H1(mu_o) S (1 + (l^2 + 45 m / 64) mu_i mu_o + l (mu_i + mu_o))
// / (6 pi (mu_i + mu_o)). (The exact cos(phi) mode is twice this.)
double first_mode(double c, double mu_i, double mu_o, double h1_i, double h1_o, const FirstModeConstants& k);
// Eq. 22 with the fits Eq. 23-27.
double first_mode_fitted(double c, double mu_i, double mu_o);

// Eq. 30: H0(mu_i) H0(mu_o) (A + B (mu_i + mu_o) + C mu_i mu_o + D mu_i mu_o (mu_i + mu_o)
// + E mu_i^2 mu_o^2 + F (mu_i^2 + mu_o^2)) / (2 pi (mu_i + mu_o)).
double zeroth_mode(double mu_i, double mu_o, double h0_i, double h0_o, const ZerothModeConstants& k);
// Eq. 30 with the fits Eq. 31-37.
double zeroth_mode_fitted(double c, double mu_i, double mu_o);

// Fourier modes of the single scattering Eq. 10 with the three-term phase function (Eq. 8):
// m = 0, the term of Eq. 38: c (45 mu_i^2 (3 mu_o^2 - 1) + 256 mu_i mu_o - 45 mu_o^2 + 207) / (768 pi (mu_i + mu_o)).
double single_scattering_zeroth_mode(double c, double mu_i, double mu_o);
// m = 1 as subtracted in Eq. 28: c (45 mu_i mu_o + 64) S / (384 pi (mu_i + mu_o)).
double single_scattering_first_mode_published(double c, double mu_i, double mu_o);
// m = 1 by expanding Eq. 10: c (45 mu_i mu_o + 64) S / (192 pi (mu_i + mu_o)) (the true one).
double single_scattering_first_mode(double c, double mu_i, double mu_o);
// m = 2: 15 c S^2 / (256 pi (mu_i + mu_o)).
double single_scattering_second_mode(double c, double mu_i, double mu_o);

// Fourier coefficient of order m of the single scattering Eq. 10 by quadrature
// over phi (composite Gauss-Legendre graded toward phi = 0, where the exact
// phase function has a square-root kink at mu_i = mu_o), with the exact phase
// function (Eq. 1) or its three-term truncation (Eq. 8). |error| < 1e-12 relative.
enum class PhaseModel { exact, three_term };
double single_scattering_mode_numeric(double c, double mu_i, double mu_o, int m, PhaseModel phase);

// Multiple-scattering zeroth mode, Eq. 38: f^(0) (Eq. 30, fits) minus the m = 0 single scattering.
double multiple_zeroth_mode_fitted(double c, double mu_i, double mu_o);

// Multiple-scattering first mode f_m^(1).
enum class FirstModeVariant {
  published,     // Eq. 28: Eq. 22 - 384 pi term
  subtract_192,  // Eq. 22 - 192 pi term (only the subtracted term fixed; wrong at O(c))
  corrected,     // 2 x Eq. 22 - 192 pi term = 2 x published (agrees with the exact solution)
  fast,          // Eq. 29 (TuringBot fit, no H-function)
};
// With the fits Eq. 23-27 (the `fast` variant ignores them).
double multiple_first_mode_fitted(double c, double mu_i, double mu_o, FirstModeVariant variant);
// Eq. 29: -0.0117 c atan(c) S sqrt(tanh(mu_i + mu_i mu_o + mu_o)) / (mu_i + mu_o).
double multiple_first_mode_fast(double c, double mu_i, double mu_o);
// Combine a first mode value f1 (Eq. 22 form) with the variant's subtraction/scale.
double multiple_first_mode_from(double first_mode_eq22, double c, double mu_i, double mu_o, FirstModeVariant variant);

}  // namespace mcref::lambert_sphere
