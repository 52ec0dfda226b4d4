#pragma once
// The analytic Lambertian-sphere BRDF (d'Eon 2021, Eq. 11-12 with Eq. 21):
//   f_r = f1 + f_m^(0) + f_m^(1) cos(phi),   f_m^(2) = 0,
// f1 the exact single scattering (Eq. 10), f_m^(0) Eq. 38, f_m^(1) Eq. 28 or a variant.
//
// sr^-1 WITHOUT the cosine; omega_i, omega_o point away from the surface; z is
// the macro normal; phi = phi_o - phi_i, phi = 0 back toward the light, phi = pi
// the mirror side (DESIGN.md and d'Eon agree, see fourier_modes.h); c = particle
// albedo in [0, 1].
//
// Ingredients can be swapped one by one, so that a validation report can show
// the published model, the corrected one, and the error of each fit:
//   first_mode:      FirstModeVariant (fourier_modes.h); `published` is Eq. 28.
//   h1:              H^(1) by Eq. 23-25 as printed, by the log-separable reading
//                    of Eq. 23-25 (h_functions.h), or exact (Eq. 16);
//   exact_h0:        H^(0) exact (Eq. 16) instead of Eq. 31-32;
//   exact_constants: l, m, A..F from the exact three-term solution instead of
//                    Eq. 26-27, 33-37 (mode_constants.h; needs c < 1, ~0.4 s).
// Max relative error against ReferenceBrdf, measured (tests, mu in [0.1, 1]):
// published 34 % (c = 0.3) .. 2 % (c = 0.99); corrected with Eq. 23 as printed
// 104 % .. 29 %; corrected with the log-separable H^(1) 1.5 % .. 4.5 % (worst at
// grazing mirror side, from the H^(0) fit); all ingredients exact, f_m^(2) = 0: 1 %.
#include <memory>

#include "models/core/vec.h"
#include "models/lambert_sphere/fourier_modes.h"
#include "models/radiative_transfer/h_function.h"

namespace mcref::lambert_sphere {

enum class H1Source { published_fit, log_separable_fit, exact };

struct BrdfOptions {
  FirstModeVariant first_mode = FirstModeVariant::published;
  H1Source h1 = H1Source::published_fit;
  bool exact_h0 = false;
  bool exact_constants = false;
};

// One albedo, built once: exact H-functions are tabulated (~0.1 s each), then
// each evaluation costs a few microseconds.
class Brdf {
 public:
  // tabulate = false evaluates exact H-functions by Fock's integral per call
  // (~0.2 ms) instead of building tables.
  Brdf(double c, const BrdfOptions& options, bool tabulate = true);
  explicit Brdf(double c) : Brdf(c, BrdfOptions{}) {}

  // 0 if mu_i <= 0 or mu_o <= 0.
  double operator()(double mu_i, double mu_o, double phi) const;
  double operator()(const Vec3& wi, const Vec3& wo) const;
  double h0(double mu) const;
  double h1(double mu) const;
  double zeroth_mode(double mu_i, double mu_o) const;           // f^(0), Eq. 30
  double first_mode_eq22(double mu_i, double mu_o) const;       // f^(1), Eq. 22 as printed
  double multiple_zeroth_mode(double mu_i, double mu_o) const;  // f_m^(0), Eq. 38
  double multiple_first_mode(double mu_i, double mu_o) const;   // f_m^(1), per variant
  double albedo() const { return c_; }
  const BrdfOptions& options() const { return options_; }

 private:
  double c_;
  BrdfOptions options_;
  FirstModeConstants first_;
  ZerothModeConstants zeroth_;
  std::shared_ptr<const radiative_transfer::HTable> table0_, table1_;
};

// Eq. 11-12 evaluated directly (the Brdf above built with tabulate = false).
// With all-fit options (the default) this is cheap; exact options cost per call.
double brdf(double c, double mu_i, double mu_o, double phi, const BrdfOptions& options = {});
double brdf(double c, const Vec3& wi, const Vec3& wo, const BrdfOptions& options = {});

}  // namespace mcref::lambert_sphere
