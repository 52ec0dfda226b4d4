#pragma once
// Isotropic scattering in a semi-infinite medium (Chandrasekhar 1960):
// characteristic function Psi(mu) = albedo / 2, dispersion function
// K(t) = 1 - albedo atan(t) / t, and the half-space BRDFs.
//
// BRDF conventions (DESIGN.md): f_r in sr^-1 WITHOUT the cosine factor;
// mu_i, mu_o are the cosines of omega_i, omega_o, both pointing away from the
// surface; the isotropic BRDF does not depend on the relative azimuth.
// Extinction is 1 per unit length; albedo in [0, 1].
#include "models/radiative_transfer/h_function.h"

namespace mcref::radiative_transfer {

// K(t) = 1 - albedo atan(t)/t (d'Eon Eq. 17 with Psi = albedo/2); a series for
// t < 1/4 keeps relative accuracy as K -> 0 at albedo = 1.
double isotropic_dispersion(double albedo, double t);

// Chandrasekhar's H(mu) for isotropic scattering by Fock's integral (Eq. 16),
// |error| < 1e-12 measured. H(1) = 2.9078105 at albedo 1.
double h_isotropic(double albedo, double mu);

// Tabulated H for one albedo (see HTable).
HTable isotropic_h_table(double albedo);

// Single scattering: albedo / (4 pi (mu_i + mu_o)). 0 if mu_i or mu_o <= 0.
double single_scattering_brdf_isotropic(double albedo, double mu_i, double mu_o);

// All orders: albedo H(mu_i) H(mu_o) / (4 pi (mu_i + mu_o)). 0 if mu_i or mu_o <= 0.
double brdf_isotropic(double albedo, double mu_i, double mu_o);

// One albedo, H tabulated once: the BRDFs above at ~1 us each.
class IsotropicHalfSpace {
 public:
  explicit IsotropicHalfSpace(double albedo);
  double albedo() const { return albedo_; }
  double h(double mu) const { return table_(mu); }
  double single_scattering(double mu_i, double mu_o) const;
  double brdf(double mu_i, double mu_o) const;  // all orders
  double multiple_scattering(double mu_i, double mu_o) const { return brdf(mu_i, mu_o) - single_scattering(mu_i, mu_o); }
  // Exact directional-hemispherical albedo 2 pi \int_0^1 f_r mu_o dmu_o
  // = 1 - H(mu_i) sqrt(1 - albedo) (Chandrasekhar 1960).
  double directional_albedo(double mu_i) const;

 private:
  double albedo_;
  HTable table_;
};

}  // namespace mcref::radiative_transfer
