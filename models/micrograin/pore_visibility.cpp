#include "models/micrograin/pore_visibility.h"

#include <algorithm>
#include <cmath>

#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"

namespace mcref::micrograin {

namespace {

// Angle in (-pi, pi].
double wrap(double a) {
  a = std::remainder(a, 2 * kPi);
  return a <= -kPi ? a + 2 * kPi : a;
}

// 1/2 ∫_{x0}^{x1} (1 / (c^2 cos^2 x + sin^2 x) - 1) dx for -pi/2 <= x0 <= x1 <= pi/2,
// antiderivative atan2(sin x, c cos x) / c - x (continuous on [-pi/2, pi/2]).
double half_excess(double c, double x0, double x1) {
  if (x1 <= x0) return 0.0;
  auto F = [c](double x) { return std::atan2(std::sin(x), c * std::cos(x)) / c - x; };
  return 0.5 * (F(x1) - F(x0));
}

// Direction d's excess over the arc of azimuths centred on `axis` of half-width pi/2
// (relative to d's own azimuth phi_d): the intersection of that arc with d's half-plane.
double arc_excess(double cos_d, double phi_d, double axis) {
  const double delta = wrap(axis - phi_d);
  const double lo = std::max(delta - kPi / 2, -kPi / 2), hi = std::min(delta + kPi / 2, kPi / 2);
  return half_excess(cos_d, lo, hi);
}

}  // namespace

double pore_shadow_union_area(Vec3 i, Vec3 o) {
  const double si = std::hypot(i.x, i.y), so = std::hypot(o.x, o.y);
  const double ci = i.z / std::hypot(si, i.z), co = o.z / std::hypot(so, o.z);
  const double phi_i = std::atan2(i.y, i.x), phi_o = std::atan2(o.y, o.x);
  // Horizontal parts (normalised directions): u_d(psi) = psi_hat . d_h.
  const double ix = si > 0 ? i.x / std::hypot(si, i.z) : 0, iy = si > 0 ? i.y / std::hypot(si, i.z) : 0;
  const double ox = so > 0 ? o.x / std::hypot(so, o.z) : 0, oy = so > 0 ? o.y / std::hypot(so, o.z) : 0;
  const double dx = ix - ox, dy = iy - oy;
  if (dx * dx + dy * dy == 0) return arc_excess(ci, phi_i, phi_i);  // i == o: one half-ellipse, Eq. 22
  // u_i >= u_o on the half-plane around axis = azimuth of (d_i - d_o)_h, u_o on the other.
  const double axis = std::atan2(dy, dx);
  return arc_excess(ci, phi_i, axis) + arc_excess(co, phi_o, axis + kPi);
}

double pore_visibility_union(const GrainField& f, Vec3 i, Vec3 o) {
  // exp(-rho' A) = (1 - tau0)^(A / pi)
  return std::exp(std::log1p(-f.tau0) * pore_shadow_union_area(to_unit_direction(f, i), to_unit_direction(f, o)) / kPi);
}

double pore_visibility_product(const GrainField& f, Vec3 i, Vec3 o) {
  const double open = 1 - f.tau0;
  return ((1 - tau_plus(f, i)) / open) * ((1 - tau_plus(f, o)) / open);  // Eq. 22, 23
}

double base_visibility_union(const GrainField& f, Vec3 i, Vec3 o) {
  return (1 - f.tau0) * pore_visibility_union(f, i, o);
}

}  // namespace mcref::micrograin
