#include "models/micrograin/two_way_masking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "models/micrograin/shadow_set.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {

// g(t) = a0 + a1 cos t + b1 sin t + a2 cos 2t + b2 sin 2t and g'(t).
struct Trig2 {
  double a0, a1, b1, a2, b2;
  double value(double t, double& slope) const {
    const double c = std::cos(t), s = std::sin(t), c2 = (c - s) * (c + s), s2 = 2 * s * c;
    slope = -a1 * s + b1 * c - 2 * a2 * s2 + 2 * b2 * c2;
    return a0 + a1 * c + b1 * s + a2 * c2 + b2 * s2;
  }
};

// Root of g in [a, b], where g(a) and g(b) differ in sign and g is monotone:
// Newton steps kept inside the bracket, bisection otherwise.
double refine_root(const Trig2& g, double a, double b, double ga) {
  double t = 0.5 * (a + b);
  for (int it = 0; it < 100 && b - a > 1e-15 * (1 + std::fabs(t)); ++it) {
    double slope;
    const double gt = g.value(t, slope);
    if (gt == 0) return t;
    if ((gt < 0) == (ga < 0)) {
      a = t;
      ga = gt;
    } else {
      b = t;
    }
    const double newton = t - gt / slope;
    t = (slope != 0 && newton > a && newton < b) ? newton : 0.5 * (a + b);
  }
  return t;
}

// Parameters t in [t0, t1] where g changes sign. The interval is split until each
// piece is certified by |g''| <= m2: free of roots (|g| beyond its possible change
// about the midpoint) or monotone (|g'| beyond its), or g cannot exceed `floor`
// there (the curves agree to rounding), or it is narrower than 1e-9: a root pair
// missed there bounds an area of the order of its width cubed.
void sign_changes(const Trig2& g, double t0, double t1, double floor, std::vector<double>& roots) {
  const double m2 = std::hypot(g.a1, g.b1) + 4 * std::hypot(g.a2, g.b2);
  struct Piece {
    double a, b, ga, gb;
  };
  double slope;
  std::vector<Piece> stack{{t0, t1, g.value(t0, slope), g.value(t1, slope)}};
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    const double w = p.b - p.a, m = 0.5 * (p.a + p.b);
    double gm_slope;
    const double gm = g.value(m, gm_slope);
    const double change = std::fabs(gm_slope) * w / 2 + m2 * w * w / 8;
    const bool sign_change = (p.ga < 0) != (p.gb < 0);
    if (std::fabs(gm) > change) continue;  // no root
    if (std::fabs(gm_slope) > m2 * w / 2 || std::fabs(gm) + change <= floor || w <= 1e-9) {
      if (sign_change) roots.push_back(refine_root(g, p.a, p.b, p.ga));
      continue;
    }
    stack.push_back({p.a, m, p.ga, gm});
    stack.push_back({m, p.b, gm, p.gb});
  }
}

// Azimuths where r_i = r_o beyond the disc: the points of E_i's arc on E_o within
// o's arc. With E_i's point P(t) in o's frame (u, v), f_o(P(t)) = (u cos theta_o +
// h sin theta_o)^2 + v^2 - 1 (> 0 outside E_o: r_i > r_o there) is a trigonometric
// polynomial of degree 2 in t.
void crossings(const ShadowSet& ki, const ShadowSet& ko, std::vector<double>& cuts) {
  const double dphi = ko.phi - ki.phi, cd = std::cos(dphi), sd = std::sin(dphi);
  const double p = -ki.h * ki.s / ki.c, q = 1 / ki.c;  // P(t) = (p + q cos t, sin t)
  // u cos theta_o + h sin theta_o = U0 + U1 cos t + U2 sin t, v = V0 + V1 cos t + V2 sin t.
  const double U0 = ko.c * cd * p + ko.h * ko.s, U1 = ko.c * cd * q, U2 = ko.c * sd;
  const double V0 = -sd * p, V1 = -sd * q, V2 = cd;
  const double quad = U1 * U1 + U2 * U2 + V1 * V1 + V2 * V2;
  const Trig2 g{U0 * U0 + V0 * V0 + 0.5 * quad - 1, 2 * (U0 * U1 + V0 * V1), 2 * (U0 * U2 + V0 * V2),
                0.5 * (U1 * U1 - U2 * U2 + V1 * V1 - V2 * V2), U1 * U2 + V1 * V2};
  // Rounding floor of g: a few ulps of its largest terms.
  const double floor = 64 * std::numeric_limits<double>::epsilon() * (U0 * U0 + V0 * V0 + quad + 1);
  std::vector<double> roots;
  sign_changes(g, -ki.tk, ki.tk, floor, roots);
  for (double t : roots) {
    const double x = p + q * std::cos(t), y = std::sin(t);
    if ((x * cd + y * sd) * ko.s < ko.h * ko.c) continue;  // outside o's half-plane: r_o = rs there
    cuts.push_back(ki.phi + std::atan2(y, x));
  }
}

}  // namespace

double cap_shadow_union_area(Vec3 i_unit, Vec3 o_unit, double h) {
  const ShadowSet ki(i_unit, h), ko(o_unit, h);
  if (!ko.has_arc()) return ki.excess();  // K_o is the disc, inside K_i
  if (!ki.has_arc()) return ko.excess();
  // Cut the circle of azimuths where the boundary of K_i U K_o changes curve:
  // the kinks of either set and the crossings of the two ellipse arcs.
  const double psi0 = ki.phi - kPi;  // outside i's arc
  std::vector<double> cuts{ki.phi - ki.psik, ki.phi + ki.psik, ko.phi - ko.psik, ko.phi + ko.psik};
  crossings(ki, ko, cuts);
  for (double& a : cuts) a = psi0 + std::fmod(std::fmod(a - psi0, 2 * kPi) + 2 * kPi, 2 * kPi);
  cuts.push_back(psi0);
  cuts.push_back(psi0 + 2 * kPi);
  std::sort(cuts.begin(), cuts.end());
  // Between cuts the boundary is the disc's (excess 0) or one ellipse arc's, the
  // one farther out at the piece's middle: its sector in closed form.
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], b = cuts[k + 1], m = 0.5 * (a + b);
    if (b - a <= 0) continue;
    const bool in_i = std::fabs(std::remainder(m - ki.phi, 2 * kPi)) < ki.psik;
    const bool in_o = std::fabs(std::remainder(m - ko.phi, 2 * kPi)) < ko.psik;
    if (!in_i && !in_o) continue;
    const bool use_i = in_i && (!in_o || ki.ellipse_radius(std::remainder(m - ki.phi, 2 * kPi)) >=
                                             ko.ellipse_radius(std::remainder(m - ko.phi, 2 * kPi)));
    const ShadowSet& k_top = use_i ? ki : ko;
    sum += k_top.arc_excess(k_top.param(a), k_top.param(b), b - a);
  }
  return sum;
}

double distant_masking_union(const GrainField& f, Vec3 i, Vec3 o, double h) {
  // exp(-rho' A) = (1 - tau0)^(A / pi)
  return std::exp(std::log1p(-f.tau0) * cap_shadow_union_area(to_unit_direction(f, i), to_unit_direction(f, o), h) / kPi);
}

}  // namespace mcref::micrograin
