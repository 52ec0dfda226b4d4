#include "models/micrograin/shadow_set.h"

#include <algorithm>
#include <cmath>

namespace mcref::micrograin {

ShadowSet::ShadowSet(Vec3 d, double height) {
  const double sd = std::hypot(d.x, d.y), n = std::hypot(sd, d.z);
  s = sd / n;
  c = d.z / n;
  phi = std::atan2(d.y, d.x);
  h = height;
  rs = std::sqrt(std::max(0.0, 1 - h * h));
  tk = psik = -1;
  if (h >= s) return;  // the line x = h cot theta misses E: no shadow beyond the disc
  const double ck = h / s;  // cos t_k; the kinks are (h cot theta, ±sin t_k)
  const double sk = std::sqrt((1 - ck) * (1 + ck));
  tk = std::atan2(sk, ck);
  psik = std::atan2(sk, ck * c);
}

double ShadowSet::ellipse_radius(double x) const {
  const double cx = std::cos(x), sx = std::sin(x), u = s * cx;
  // 1 - u^2 = cos^2 theta cos^2 x + sin^2 x and disc = (1 - u^2)(1 - h^2) + h^2 cos^2 theta,
  // written without the cancellation of 1 - u^2 near grazing (u -> 1).
  const double w = c * c * cx * cx + sx * sx;
  return (-u * h * c + std::sqrt(w * rs * rs + h * h * c * c)) / w;
}

double ShadowSet::radius(double psi) const {
  if (!has_arc()) return rs;
  const double x = std::remainder(psi - phi, 2 * kPi);
  if (std::fabs(x) >= psik) return rs;
  return std::max(rs, ellipse_radius(x));
}

double ShadowSet::param(double psi) const {
  const double x = std::remainder(psi - phi, 2 * kPi), r = ellipse_radius(x);
  // (r cos x + h tan theta) cos theta = cos t, r sin x = sin t
  return std::atan2(r * std::sin(x), r * c * std::cos(x) + h * s);
}

double ShadowSet::arc_excess(double t1, double t2, double dpsi) const {
  return 0.5 * ((t2 - t1) / c - h * (s / c) * (std::sin(t2) - std::sin(t1)) - rs * rs * dpsi);
}

double shadow_set_radius(Vec3 d_unit, double h, double psi) { return ShadowSet(d_unit, h).radius(psi); }

}  // namespace mcref::micrograin
