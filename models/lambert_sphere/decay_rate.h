#pragma once
// Asymptotic decay of the diffuse radiance deep in a Lambert-sphere medium
// (three-term phase function, d'Eon 2021 Sec. 3.1): exp(-s0 tau) at optical
// depth tau, s0 = 1 / nu0 with nu0 the discrete eigenvalue of the m = 0
// problem, the root of the dispersion function on the imaginary axis:
//   K^(0)(i s) = 1 - 2 \int_0^1 Psi^(0)(mu) / (1 - s^2 mu^2) dmu = 0
// (Eq. 18 continued to t = i s; K(0) is Eq. 32).

namespace mcref::lambert_sphere {

// K^(0)(i s) for s in [0, 1).
double dispersion_imaginary(double c, double s);

// s0 in (0, 1] for albedo c in [0, 1): the root above, or 1 where it is so
// close to 1 (c -> 0) that the uncollided exp(-tau) decays as slowly.
// Diffusion's 1 / sqrt(3 (1 - c)(1 - c g)) is its c -> 1 limit.
double decay_rate(double c);

}  // namespace mcref::lambert_sphere
