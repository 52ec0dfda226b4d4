#pragma once
// Constants of the Fourier modes of the three-term half-space (d'Eon 2021):
// the published fits (Eq. 26-27, 33-37), and the same constants computed
// without fits from the exact numerical solution (radiative_transfer::ThreeTermHalfSpace),
// which is what the paper's Fig. 3 and Fig. 6 call "Exact".
// c = particle albedo in [0, 1].

namespace mcref::lambert_sphere {

// l and m of the first mode (Eq. 22).
struct FirstModeConstants {
  double l = 0, m = 1;
};
// Eq. 26: l ~ -0.00473696 c^2 - 0.0589037 c;  Eq. 27: m ~ 0.44038 c + 1.
FirstModeConstants first_mode_constants_fit(double c);

// A..F of the zeroth mode (Eq. 30).
struct ZerothModeConstants {
  double A = 0, B = 0, C = 0, D = 0, E = 0, F = 0;
};
// Eq. 33 (A, E, exact relations) and Eq. 34-37 (B, C, D, F, fits in s = sqrt(1-c)).
ZerothModeConstants zeroth_mode_constants_fit(double c);

// The same constants from the exact three-term solution: the exact mode is
// divided by its H-function factor, e.g. f^(0) 2 pi (mu_i + mu_o) / (H0(mu_i) H0(mu_o)),
// and the polynomial of Eq. 30 (resp. Eq. 22) is fitted by least squares on a
// 6 x 6 grid of (mu_i, mu_o). The polynomial form itself is exact (residual
// ~1e-13, see tests). ~0.2 s each. c in (0, 0.9999] for m = 0, (0, 1] for m = 1.
ZerothModeConstants zeroth_mode_constants_exact(double c);
// For the first mode the scale is also free: `scale` is 2 for every c, i.e. the
// exact first mode is twice Eq. 22 (see fourier_modes.h).
struct ExactFirstModeConstants {
  double l = 0, m = 1, scale = 1;
};
ExactFirstModeConstants first_mode_constants_exact(double c);

}  // namespace mcref::lambert_sphere
