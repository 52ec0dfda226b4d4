#include "models/micrograin/projected_area.h"

#include <algorithm>
#include <cmath>

#include "models/core/quadrature.h"
#include "models/micrograin/shadow_set.h"

namespace mcref::micrograin {

double cap_cross_section(double h) { return kPi * (1 - h * h); }

// The excess of the shadow set K_i(h) over the disc (shadow_set.h).
double cap_shadow_area(double theta_i, double h) { return ShadowSet(spherical_direction(theta_i, 0), h).excess(); }

double cap_shadow_area(Vec3 i_unit, double h) { return ShadowSet(i_unit, h).excess(); }

double projected_cap_area(double theta_i, double h) {
  return cap_cross_section(h) + cap_shadow_area(theta_i, h);  // vNDF Eq. 5
}

double projected_cap_area(Vec3 i_unit, double h) {
  return cap_cross_section(h) + cap_shadow_area(i_unit, h);  // vNDF Eq. 5
}

double projected_cap_area_numeric(double theta_i, double h, int panels) {
  const double t = std::tan(theta_i);
  const double r2 = 1 - h * h;
  // Y(x)^2 = max over z in [h, 1] of g(z) = 1 - z^2 - (x + (z - h) t)^2.
  auto y_extent = [&](double x) {
    const double z = std::clamp(t * (h * t - x) / (1 + t * t), h, 1.0);  // g'(z) = 0
    const double u = x + (z - h) * t;
    return std::sqrt(std::max(0.0, 1 - z * z - u * u));
  };
  // Support in x: [x_min, sqrt(r2)], x_min the leftmost point of the union.
  // Leftmost point of the disc at height z: -(z - h) t - sqrt(1 - z^2); its
  // minimum over z is at z = max(h, sin theta_i).
  const double z_left = std::max(h, std::sin(theta_i));
  const double x_min = -(z_left - h) * t - std::sqrt(1 - z_left * z_left);
  const double x_max = std::sqrt(r2);
  // Break where the maximiser leaves the clamp (x = -h / t), a kink of Y.
  double x_break = t > 0 ? -h / t : x_min;
  x_break = std::clamp(x_break, x_min, x_max);
  auto piece = [&](double a, double b) {
    if (b <= a) return 0.0;
    // x = a + (b - a)(1 - cos s)/2, s in [0, pi]: smooth at sqrt end points.
    auto g = [&](double s) {
      const double x = a + 0.5 * (b - a) * (1 - std::cos(s));
      return y_extent(x) * 0.5 * (b - a) * std::sin(s);
    };
    return integrate_composite(g, 0.0, kPi, panels, 16);
  };
  return 2 * (piece(x_min, x_break) + piece(x_break, x_max));
}

}  // namespace mcref::micrograin
