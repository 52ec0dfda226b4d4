#include "models/lambert_sphere/reference_brdf.h"

#include <cmath>
#include <stdexcept>

#include "models/lambert_sphere/single_scattering.h"

namespace mcref::lambert_sphere {

namespace {
constexpr double kA1 = -4.0 / 3.0, kA2 = 5.0 / 16.0;  // Eq. 4 / Eq. 8
}

ReferenceBrdf::ReferenceBrdf(double c, bool include_second_mode)
    : c_(c), second_(include_second_mode), m0_(c, kA1, kA2, 0), m1_(c, kA1, kA2, 1), m2_(c, kA1, kA2, 2) {}

double ReferenceBrdf::mode(int m, double mu_i, double mu_o) const {
  switch (m) {
    case 0: return m0_.mode(mu_i, mu_o);
    case 1: return m1_.mode(mu_i, mu_o);
    case 2: return m2_.mode(mu_i, mu_o);
    default: throw std::out_of_range("ReferenceBrdf::mode: m not in {0, 1, 2}");
  }
}

double ReferenceBrdf::multiple_mode(int m, double mu_i, double mu_o) const {
  if (m < 0 || m > 2) throw std::out_of_range("ReferenceBrdf::multiple_mode: m not in {0, 1, 2}");
  const auto& s = m == 0 ? m0_ : (m == 1 ? m1_ : m2_);
  return s.mode(mu_i, mu_o) - s.single_scattering_mode(mu_i, mu_o);
}

double ReferenceBrdf::operator()(double mu_i, double mu_o, double phi) const {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  double f = single_scattering(c_, mu_i, mu_o, phi) + multiple_mode(0, mu_i, mu_o) +
             multiple_mode(1, mu_i, mu_o) * std::cos(phi);
  if (second_) f += multiple_mode(2, mu_i, mu_o) * std::cos(2 * phi);
  return f;
}

double ReferenceBrdf::operator()(const Vec3& wi, const Vec3& wo) const {
  return (*this)(wi.z, wo.z, relative_azimuth(wi, wo));
}

}  // namespace mcref::lambert_sphere
