#include "models/lambert_sphere/albedo_mapping.h"

#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/vec.h"
#include "models/lambert_sphere/fourier_modes.h"
#include "models/lambert_sphere/reference_brdf.h"

namespace mcref::lambert_sphere {

double albedo_from_kd(double kd) {
  const double q = 1 - kd;
  return (1 - 1.00425 * std::pow(q, 2.67103)) / (1 - 0.219924 * std::pow(q, 2.44559));  // Eq. 39
}

double kd_from_albedo(double c) {
  const double s = std::sqrt(1 - c);
  return (-0.453029 * (1 - c) - 0.544162 * s + 1) / (1.42931 * s + 1);  // Eq. 40
}

RoundTripError albedo_mapping_round_trip_error(int n) {
  RoundTripError e;
  for (int i = 0; i <= n; ++i) {
    const double x = static_cast<double>(i) / n;
    const double a = std::fabs(albedo_from_kd(kd_from_albedo(x)) - x);
    const double b = std::fabs(kd_from_albedo(albedo_from_kd(x)) - x);
    if (a > e.c_to_kd_to_c) { e.c_to_kd_to_c = a; e.at_c = x; }
    if (b > e.kd_to_c_to_kd) { e.kd_to_c_to_kd = b; e.at_kd = x; }
  }
  return e;
}

double spherical_albedo(const std::function<double(double, double)>& zeroth_mode) {
  const GaussLegendre rule(8);
  std::vector<double> x, w;
  auto panel = [&](double a, double b) {
    for (std::size_t i = 0; i < rule.x.size(); ++i) {
      x.push_back(0.5 * (a + b) + 0.5 * (b - a) * rule.x[i]);
      w.push_back(0.5 * (b - a) * rule.w[i]);
    }
  };
  panel(0.0, std::ldexp(1.0, -12));
  for (int j = 11; j >= 0; --j) panel(std::ldexp(1.0, -(j + 1)), std::ldexp(1.0, -j));
  double s = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t k = 0; k < x.size(); ++k) s += w[i] * w[k] * x[i] * x[k] * zeroth_mode(x[i], x[k]);
  return 4 * kPi * s;
}

double spherical_albedo_reference(double c) {
  const ReferenceBrdf ref(c);
  return spherical_albedo([&](double a, double b) {
    return single_scattering_mode_numeric(c, a, b, 0, PhaseModel::exact) + ref.multiple_mode(0, a, b);
  });
}

}  // namespace mcref::lambert_sphere
