#include "models/radiative_transfer/isotropic.h"

#include <cmath>
#include <stdexcept>

#include "models/core/vec.h"

namespace mcref::radiative_transfer {

namespace {
void check_albedo(double albedo) {
  if (!(albedo >= 0 && albedo <= 1))
    throw std::invalid_argument("radiative_transfer: isotropic albedo must be in [0, 1]");
}
}  // namespace

double isotropic_dispersion(double albedo, double t) {
  t = std::fabs(t);
  if (std::isinf(t)) return 1.0;
  if (t < 0.25) {
    // 1 - atan(t)/t = t^2/3 - t^4/5 + t^6/7 - ...; 0.25^48 < 1e-28.
    const double t2 = t * t;
    double term = t2, s = 0;
    for (int n = 1; n <= 24; ++n) {
      s += term / (2 * n + 1);
      term *= -t2;
    }
    return (1 - albedo) + albedo * s;
  }
  return 1 - albedo * std::atan(t) / t;
}

double h_isotropic(double albedo, double mu) {
  check_albedo(albedo);
  return h_function_from_dispersion([albedo](double t) { return isotropic_dispersion(albedo, t); }, mu);
}

HTable isotropic_h_table(double albedo) {
  check_albedo(albedo);
  return HTable([albedo](double) { return 0.5 * albedo; },
                [albedo](double t) { return isotropic_dispersion(albedo, t); });
}

double single_scattering_brdf_isotropic(double albedo, double mu_i, double mu_o) {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  return albedo / (4 * kPi * (mu_i + mu_o));
}

double brdf_isotropic(double albedo, double mu_i, double mu_o) {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  return albedo * h_isotropic(albedo, mu_i) * h_isotropic(albedo, mu_o) / (4 * kPi * (mu_i + mu_o));
}

IsotropicHalfSpace::IsotropicHalfSpace(double albedo)
    : albedo_(albedo), table_(isotropic_h_table(albedo)) {}

double IsotropicHalfSpace::single_scattering(double mu_i, double mu_o) const {
  return single_scattering_brdf_isotropic(albedo_, mu_i, mu_o);
}

double IsotropicHalfSpace::brdf(double mu_i, double mu_o) const {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  return albedo_ * table_(mu_i) * table_(mu_o) / (4 * kPi * (mu_i + mu_o));
}

double IsotropicHalfSpace::directional_albedo(double mu_i) const {
  return 1 - table_(mu_i) * std::sqrt(1 - albedo_);
}

}  // namespace mcref::radiative_transfer
