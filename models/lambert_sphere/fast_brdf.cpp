#include "models/lambert_sphere/fast_brdf.h"

#include <cmath>

#include "models/lambert_sphere/albedo_mapping.h"
#include "models/lambert_sphere/single_scattering.h"

namespace mcref::lambert_sphere {

double brdf_fast(double c, double mu_i, double mu_o, double phi) {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  phi = std::remainder(phi, 2 * kPi);  // [-pi, pi]
  const double s = std::sqrt(std::fmax(0.0, 1 - mu_i * mu_i) * std::fmax(0.0, 1 - mu_o * mu_o));
  const double middle = s > 0 ? 0.0151829 * (c - 0.249978) * (std::fabs(phi) + std::sqrt(mu_i * mu_o)) /
                                    (std::acos(s) / s + 0.113706)
                              : 0.0;
  const double kd = kd_from_albedo(c);
  return std::fmax(0.0, single_scattering(c, mu_i, mu_o, phi) + middle + 0.234459 * std::pow(kd, 1.85432));
}

double brdf_fast(double c, const Vec3& wi, const Vec3& wo) {
  return brdf_fast(c, wi.z, wo.z, relative_azimuth(wi, wo));
}

}  // namespace mcref::lambert_sphere
