#pragma once
// The triangle-cut parameterisation of the region under a curve (Heitz 2020,
// "Can't invert the CDF?"), the `tricut_remove_bias` step of the vNDF paper's
// Listing 3. Heitz's own listing is not in our texts; this is our derivation
// of the construction the vNDF paper describes (an area-preserving map of the
// region under an approximate pdf q onto the region under the target pdf f).
//
// A first uniform u_s picks a cut: x_a = Q^-1(u_s), Q the CDF of q. The cut
// is the segment from the curve point (x_a, f(x_a)) to the axis point
// (x_b, 0) chosen so that the area under f left of the cut equals u_s:
//   F(x_a) + (x_b - x_a) f(x_a) / 2 = u_s.
// The sliver between the cuts of u_s and u_s + du has area du; its width per
// du, times the cut's length, grows linearly from
//   w_a = (f + (x_b - x_a) f') / q   at the curve point to   w_b = 2 - w_a
// at the axis point (dx_a/du_s = 1/q). A second uniform u_t picks the point
// at fraction t of the cut with density (1 - t) w_a + t w_b, and its abscissa
// x_a + t (x_b - x_a) is distributed with density f, exactly, provided the
// cuts do not cross: 0 <= w_a <= 2 and the cut lies under the curve for every
// u_s (the vNDF paper checks this empirically, as do our tests).
#include <cmath>

namespace mcref {

struct TriangleCut {
  double x_a = 0, x_b = 0;  // the cut joins (x_a, f(x_a)) to (x_b, 0)
  double w_a = 1;           // relative sliver width at (x_a, f(x_a)); 2 - w_a at (x_b, 0)
  bool valid() const { return w_a >= 0 && w_a <= 2; }
  // The abscissa of the point at fraction t(u_t) along the cut.
  double point(double u_t) const {
    // Invert w_a t + (1 - w_a) t^2 = u_t (stable for every w_a in [0, 2]).
    const double r = w_a * w_a + 4 * (1 - w_a) * u_t;
    const double den = w_a + std::sqrt(r > 0 ? r : 0.0);
    const double t = den > 0 ? 2 * u_t / den : 0.0;
    return x_a + t * (x_b - x_a);
  }
};

// x_a: the approximate sample Q^-1(u_s); f, df, q: the target pdf, its
// derivative and the approximate pdf at x_a; d = 2 (u_s - F(x_a)), F the
// target CDF. The cut does not change when f, df, q and d are scaled
// together, so all four may carry any common positive factor (e.g. an
// unnormalised target).
inline TriangleCut triangle_cut_scaled(double x_a, double f, double df, double q, double d) {
  TriangleCut c;
  c.x_a = c.x_b = x_a;
  if (!(f > 0) || !(q > 0)) return c;  // an end point of the domain (u_s = 0 or 1)
  const double inv_fq = 1 / (f * q);    // one division for both
  c.x_b = x_a + d * q * inv_fq;
  c.w_a = (f * f + d * df) * inv_fq;
  return c;
}

// triangle_cut_scaled(x_a, f, df, q, d).point(u_t) with one division instead
// of three: with P = f q and W = f^2 + d df (so w_a = W / P and
// x_b - x_a = d q / P), the root t = 2 u_t / (w_a + sqrt(w_a^2 + 4 (1 - w_a) u_t))
// makes the point x_a + 2 u_t d q / (W + sqrt(W^2 + 4 P (P - W) u_t)).
inline double triangle_cut_point(double x_a, double f, double df, double q, double d, double u_t) {
  if (!(f > 0) || !(q > 0)) return x_a;  // an end point of the domain
  const double P = f * q, W = f * f + d * df, r = W * W + 4 * P * (P - W) * u_t;
  const double den = W + std::sqrt(r > 0 ? r : 0.0);
  return den > 0 ? x_a + 2 * u_t * d * q / den : x_a;
}

// u_s: the uniform that gave x_a = Q^-1(u_s), Q the CDF of q; f, F, df: the
// target pdf, its CDF and its derivative at x_a; q: the approximate pdf at x_a.
inline TriangleCut triangle_cut(double u_s, double x_a, double f, double F, double df, double q) {
  return triangle_cut_scaled(x_a, f, df, q, 2 * (u_s - F));
}

}  // namespace mcref
