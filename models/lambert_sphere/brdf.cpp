#include "models/lambert_sphere/brdf.h"

#include <cmath>
#include <stdexcept>

#include "models/lambert_sphere/h_functions.h"
#include "models/lambert_sphere/single_scattering.h"

namespace mcref::lambert_sphere {

Brdf::Brdf(double c, const BrdfOptions& options, bool tabulate) : c_(c), options_(options) {
  if (!(c >= 0 && c <= 1)) throw std::invalid_argument("lambert_sphere::Brdf: albedo must be in [0, 1]");
  if (tabulate && c > 0) {
    if (options.exact_h0) table0_ = std::make_shared<radiative_transfer::HTable>(h_table(0, c));
    if (options.h1 == H1Source::exact) table1_ = std::make_shared<radiative_transfer::HTable>(h_table(1, c));
  }
  if (options.exact_constants && c > 0) {
    const ExactFirstModeConstants k = first_mode_constants_exact(c);
    first_ = {k.l, k.m};
    zeroth_ = zeroth_mode_constants_exact(c);
  } else {
    first_ = first_mode_constants_fit(c);
    zeroth_ = zeroth_mode_constants_fit(c);
  }
}

double Brdf::h0(double mu) const {
  if (!options_.exact_h0) return h0_fit(c_, mu);             // Eq. 31-32
  return table0_ ? (*table0_)(mu) : h_exact(0, c_, mu);      // Eq. 16
}

double Brdf::h1(double mu) const {
  switch (options_.h1) {
    case H1Source::published_fit: return h1_fit(c_, mu);                 // Eq. 23-25
    case H1Source::log_separable_fit: return h1_fit_log_separable(c_, mu);
    case H1Source::exact: return table1_ ? (*table1_)(mu) : h_exact(1, c_, mu);  // Eq. 16
  }
  throw std::invalid_argument("lambert_sphere::Brdf: unknown H1Source");
}

double Brdf::zeroth_mode(double mu_i, double mu_o) const {
  return lambert_sphere::zeroth_mode(mu_i, mu_o, h0(mu_i), h0(mu_o), zeroth_);
}

double Brdf::first_mode_eq22(double mu_i, double mu_o) const {
  return first_mode(c_, mu_i, mu_o, h1(mu_i), h1(mu_o), first_);
}

double Brdf::multiple_zeroth_mode(double mu_i, double mu_o) const {
  return zeroth_mode(mu_i, mu_o) - single_scattering_zeroth_mode(c_, mu_i, mu_o);  // Eq. 38
}

double Brdf::multiple_first_mode(double mu_i, double mu_o) const {
  if (options_.first_mode == FirstModeVariant::fast) return multiple_first_mode_fast(c_, mu_i, mu_o);  // Eq. 29
  return multiple_first_mode_from(first_mode_eq22(mu_i, mu_o), c_, mu_i, mu_o, options_.first_mode);
}

double Brdf::operator()(double mu_i, double mu_o, double phi) const {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  return single_scattering(c_, mu_i, mu_o, phi) + multiple_zeroth_mode(mu_i, mu_o) +
         multiple_first_mode(mu_i, mu_o) * std::cos(phi);  // Eq. 11-12, f_m^(2) = 0 (Eq. 21)
}

double Brdf::operator()(const Vec3& wi, const Vec3& wo) const {
  return (*this)(wi.z, wo.z, relative_azimuth(wi, wo));
}

double brdf(double c, double mu_i, double mu_o, double phi, const BrdfOptions& options) {
  return Brdf(c, options, /*tabulate=*/false)(mu_i, mu_o, phi);
}

double brdf(double c, const Vec3& wi, const Vec3& wo, const BrdfOptions& options) {
  return Brdf(c, options, /*tabulate=*/false)(wi, wo);
}

}  // namespace mcref::lambert_sphere
