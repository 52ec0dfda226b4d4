#pragma once
// Sampling the Lambertian-sphere phase function (d'Eon 2021, Sec. 2.0.1).
//
// All functions here are about mu, the cosine between the incoming propagation
// direction and the scattered direction (see phase_function.h); the azimuth
// about the propagation direction is uniform.
#include "models/core/vec.h"

namespace mcref::lambert_sphere {

// Marginal density of mu on [-1, 1]: 2 pi p(mu) = 4 (sqrt(1-mu^2) - mu acos mu) / (3 pi).
double phase_pdf_mu(double mu);

// Exact CDF of mu, integrating Eq. 1:
//   F(mu) = 5/6 + mu sqrt(1-mu^2)/pi + asin(mu)/(3pi) - 2 mu^2 acos(mu)/(3pi)
//         = 1 - Q(acos mu),  Q(t) = (4t + 2t cos 2t - 3 sin 2t) / (6pi)  (t = deflection angle).
double phase_cdf_mu(double mu);
// 1 - F(mu) = Q(acos mu), with Q's series for t < 1/2 (Q ~ 4 t^5 / (45 pi)): keeps
// its relative accuracy in the forward tail, where 1 - phase_cdf_mu rounds to 0.
double phase_ccdf_mu(double mu);

// Numerical inverse of the exact CDF: safeguarded Newton in t = acos(mu),
// |mu - F^{-1}(xi)| < 1e-13.
double phase_inverse_cdf(double xi);

// Eq. 5, exact sampler from three uniforms in [0, 1):
//   mu = sqrt((1 - u1)(1 - u2)) sin(2 pi u3) - sqrt(u1 u2).
double sample_phase_cosine_exact(double u1, double u2, double u3);

// Eq. 6, approximate inverse CDF from one uniform:
//   mu(xi) = 1 - 2 (1 - xi^(0.0401885 xi + 1.01938))^0.397225.
double sample_phase_cosine_approx(double xi);

// Largest |Eq. 6 - F^{-1}| over xi in [0, 1]: a scan of `grid_points` + 1
// uniform points, then golden-section refinement around the worst one.
struct InverseCdfError {
  double max_abs_error = 0;  // in mu
  double xi = 0;             // where it occurs
};
InverseCdfError approximate_inverse_cdf_max_error(int grid_points = 200000);

// New propagation direction for a photon travelling along unit vector
// `propagation`, deflected by cosine mu (from one of the samplers above) with
// azimuth 2 pi u_phi about the propagation direction.
Vec3 scattered_direction(const Vec3& propagation, double mu, double u_phi);

}  // namespace mcref::lambert_sphere
