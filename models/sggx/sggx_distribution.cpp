#include "models/sggx/sggx_distribution.h"

#include <cmath>
#include <stdexcept>

#include "models/core/frame.h"
#include "models/core/warp.h"

namespace mcref::sggx {

Sggx from_matrix(const Mat3& S) {
  Sggx s;
  s.S = S;
  if (!cholesky_lower(S, s.L))
    throw std::invalid_argument("SGGX matrix S must be symmetric positive definite");
  s.S_inv = inverse(S);
  s.sqrt_det = s.L(0, 0) * s.L(1, 1) * s.L(2, 2);  // det L = sqrt(det S)
  return s;
}

namespace {
Vec3 unit_axis(Vec3 wp) {
  const double n = length(wp);
  if (!(n > 0) || !std::isfinite(n)) throw std::invalid_argument("SGGX orientation must be non-zero");
  return wp / n;
}
void check_alpha(double alpha) {
  if (!(alpha > 0) || !std::isfinite(alpha)) throw std::invalid_argument("SGGX alpha must be > 0");
}
}  // namespace

Sggx surface_like(double alpha, Vec3 wp) {
  check_alpha(alpha);
  const Vec3 a = unit_axis(wp);
  return from_matrix(identity3() * (alpha * alpha) + outer(a, a) * (1 - alpha * alpha));
}

Sggx fiber_like(double alpha, Vec3 wp) {
  check_alpha(alpha);
  const Vec3 a = unit_axis(wp);
  return from_matrix(identity3() + outer(a, a) * (alpha * alpha - 1));
}

double ndf_eq7_as_printed(const Sggx& s, double alpha, Vec3 m) {
  const double q = quadratic_form(s.S_inv, m) / dot(m, m);
  return 1.0 / (kPi * alpha * q * q);
}

double visible_ndf(const Sggx& s, Vec3 w, Vec3 m) {
  const double c = dot(w, m);
  if (c <= 0) return 0;
  return c * ndf(s, m) / projected_area(s, w);
}

}  // namespace mcref::sggx
