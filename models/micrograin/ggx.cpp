#include "models/micrograin/ggx.h"

#include <cmath>
#include <limits>

namespace mcref::micrograin {

double ggx_ndf(double alpha, double theta_m) {
  const double c = std::cos(theta_m), s = std::sin(theta_m), a2 = alpha * alpha;
  const double d = a2 * c * c + s * s;
  return a2 / (kPi * d * d);
}

double ggx_ndf(double alpha_x, double alpha_y, Vec3 m) {
  if (m.z <= 0) return 0.0;
  const double ux = m.x / alpha_x, uy = m.y / alpha_y;
  const double d = ux * ux + uy * uy + m.z * m.z;  // = cos^2 (1 + tan^2 (...))
  return 1.0 / (kPi * alpha_x * alpha_y * d * d);
}

double ggx_lambda(double alpha, double theta) {
  const double c = std::cos(theta);
  if (c <= 0) return std::numeric_limits<double>::infinity();
  const double t = std::sin(theta) / c;
  const double x = alpha * alpha * t * t;
  return x / (2 * (std::sqrt(1 + x) + 1));  // = (-1 + sqrt(1 + x)) / 2, no cancellation
}

double smith_g1(double lambda) { return 1.0 / (1.0 + lambda); }

}  // namespace mcref::micrograin
