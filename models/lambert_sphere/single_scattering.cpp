#include "models/lambert_sphere/single_scattering.h"

#include <cmath>

#include "models/lambert_sphere/phase_function.h"

namespace mcref::lambert_sphere {

double relative_azimuth(const Vec3& wi, const Vec3& wo) {
  if ((wi.x == 0 && wi.y == 0) || (wo.x == 0 && wo.y == 0)) return 0.0;
  // atan2 of (wi_xy x wo_xy, wi_xy . wo_xy) = phi_o - phi_i in (-pi, pi].
  return std::atan2(wi.x * wo.y - wi.y * wo.x, wi.x * wo.x + wi.y * wo.y);
}

double single_scattering(double c, double mu_i, double mu_o, double phi) {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  const double s = std::sqrt(std::fmax(0.0, 1 - mu_i * mu_i) * std::fmax(0.0, 1 - mu_o * mu_o));
  return c * phase_function(-mu_i * mu_o - s * std::cos(phi)) / (mu_i + mu_o);
}

double single_scattering(double c, const Vec3& wi, const Vec3& wo) {
  if (!(wi.z > 0 && wo.z > 0)) return 0.0;
  return c * phase_function(-dot(wi, wo)) / (wi.z + wo.z);
}

}  // namespace mcref::lambert_sphere
