#include "models/micrograin/phi_conditional.h"

#include <algorithm>
#include <cmath>

#include "models/core/arc_sine.h"
#include "models/core/small_angle.h"

namespace mcref::micrograin {

PhiConditional::PhiConditional(Vec3 iu, double ct)
    : PhiConditional(iu.z, std::sqrt(std::max(0.0, 1 - iu.z * iu.z)), ct, std::sqrt(std::max(0.0, 1 - ct * ct))) {}

PhiConditional::PhiConditional(double ci, double si, double ct, double st) {
  a = si * st;
  b = ci * ct;
  shadow = si > ct;  // equivalently a > b
  if (shadow) {
    phi_q = 0.5 * kPi + asin_series(b / a);  // acos(-b / a)
    mass = 2 * (std::sqrt((a - b) * (a + b)) + b * phi_q);  // a sin phi_q = sqrt(a^2 - b^2)
  } else {
    phi_q = kPi;
    mass = 2 * kPi * b;
  }
}

double PhiConditional::tent_pdf(double phi) const {
  // Eq. 28 with P~(+-phi_q) = h0 and unit mass: (t0 - t1 y) / (mass phi_q).
  return std::fabs(phi) > phi_q ? 0.0 : (t0() - t1() * std::fabs(phi) / phi_q) / (mass * phi_q);
}

double PhiConditional::tent_fraction(double v) const {
  // The tent's CDF from 0 to y phi_q is (t0 y - t1 y^2 / 2) / mass = v (Eq. 30);
  // its stable root. With a shadow, t0 = t1 = mass: y = 2 v / (1 + sqrt(1 - 2 v)).
  const double k0 = shadow ? 1.0 : a + b, k1 = shadow ? 1.0 : 2 * a, m = shadow ? 1.0 : 2 * b;  // t0, t1, mass / (pi or mass)
  const double r = k0 * k0 - 2 * k1 * m * v;
  return std::min(1.0, 2 * m * v / (k0 + std::sqrt(std::max(0.0, r))));
}

double PhiConditional::tent_inverse(double u) const {  // Eq. 31
  return std::copysign(phi_q * tent_fraction(std::fabs(u - 0.5)), u - 0.5);
}

PhiConditional::CutTerms PhiConditional::cut_terms(double u_s, double x, double y, double sin_x, double cos_x) const {
  // Listing 3, lines 19–24, every term times mass phi_q: f = a cos x + b, f' = -a sin x,
  // the tent t0 - t1 y, and 2 (u_s - F(x)) = (2 u_s - 1) mass - 2 (a sin x + b x).
  const double d = (2 * u_s - 1) * mass - 2 * (a * sin_x + b * x);
  return {(a * cos_x + b) * phi_q, -a * sin_x * phi_q, t0() - t1() * y, d * phi_q};
}

TriangleCut PhiConditional::cut(double u_s) const {
  const double x = tent_inverse(u_s);
  const CutTerms c = cut_terms(u_s, x, std::fabs(x) / phi_q, std::sin(x), std::cos(x));
  return triangle_cut_scaled(x, c.f, c.df, c.q, c.d);
}

PhiSample PhiConditional::sample(double u_s, double u_t) const {
  const double y = tent_fraction(std::fabs(u_s - 0.5)), x = std::copysign(phi_q * y, u_s - 0.5);
  const SinCos sx = sincos_within_pi(x);  // the series (small_angle.h)
  // The point of the cut at u_t in one step (triangle_cut_point).
  const CutTerms c = cut_terms(u_s, x, y, sx.sin, sx.cos);
  const double end = triangle_cut_point(x, c.f, c.df, c.q, c.d, u_t);
  // phi = x + d, d the step along the cut (|d| < 1.3 everywhere, see the
  // tests): its sine and cosine by angle addition, without a second sincos.
  const double d = std::clamp(end, -phi_q, phi_q) - x;
  const SinCos r = sincos_small(d);
  return {x + d, sx.cos * r.cos - sx.sin * r.sin, sx.sin * r.cos + sx.cos * r.sin};
}

}  // namespace mcref::micrograin
