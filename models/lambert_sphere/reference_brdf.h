#pragma once
// Reference Lambertian-sphere half-space BRDF without any fitted constant:
//   f_r = f1 (exact phase function, Eq. 10)
//       + sum_{m=0..2} [f^(m)_3 - f1^(m)_3] cos(m phi),
// where f^(m)_3 are the exact Fourier modes of the half-space with the
// three-term phase function (Eq. 8), solved numerically
// (radiative_transfer::ThreeTermHalfSpace), and f1^(m)_3 their single-scattering
// parts. This is what d'Eon's Eq. 11-12 approximate, with the three-term
// truncation kept for multiple scattering only; include_second_mode = false
// drops m = 2 as Eq. 21 does. Conventions as in brdf.h. c in [0, 1).
#include "models/core/vec.h"
#include "models/radiative_transfer/three_term_half_space.h"

namespace mcref::lambert_sphere {

class ReferenceBrdf {
 public:
  // ~0.1 s to build.
  explicit ReferenceBrdf(double c, bool include_second_mode = true);
  double operator()(double mu_i, double mu_o, double phi) const;
  double operator()(const Vec3& wi, const Vec3& wo) const;
  // Multiple-scattering Fourier mode f_m^(m) of the three-term half-space, m = 0, 1, 2.
  double multiple_mode(int m, double mu_i, double mu_o) const;
  // All-orders mode f^(m) of the three-term half-space.
  double mode(int m, double mu_i, double mu_o) const;
  double albedo() const { return c_; }

 private:
  double c_;
  bool second_;
  radiative_transfer::ThreeTermHalfSpace m0_, m1_, m2_;
};

}  // namespace mcref::lambert_sphere
