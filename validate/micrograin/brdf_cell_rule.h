#pragma once
// The cell rule of the micrograin_brdf family (issue #15, part 4): ∫∫ g dtheta dphi
// over a (theta_o, phi) cell, g = f cos theta_o sin theta_o (smooth at the pole,
// unlike f cos theta_o in mu = cos theta_o), to kCellRelTolerance per component.
// - The cell is split where g has kinks: at theta_o = theta_i (the union masking's
//   cusp at backscatter, the specular peak at the mirror direction, and the G_dist
//   polar cuts' swap), and at phi = 0, pi (relative to phi_i) when they fall inside.
// - Pieces ending at the kink theta_i are graded toward it: x = a + (b - a) u^2
//   turns (x - a)^(k/2) into a polynomial in u. In phi, only pieces touching
//   theta_i are graded (the cusp and the peak sit at theta_o = theta_i).
// - Each piece: 4 x 4 Gauss-Legendre in (u, v), checked against 3 x 3 (a-posteriori:
//   |Q4 - Q3| bounds Q4's error, which is far smaller). While the summed estimates
//   exceed the cell's tolerance, the worst piece is split (global adaptivity): at
//   the grazing edge in theta only, 0.15 of it at the edge (a geometric mesh; there
//   g ~ (pi/2 - theta)^p, p not an integer, smooth in phi), elsewhere in four.
// The nodes depend only on the cell and theta_i until a check fails, so models of
// one table share them (geometry_memo.h).
// Status (issue #15, part 4; branch `cells`): the accuracy is not yet verified
// against the references, and the grazing cells need far more nodes than the
// former 3 x 3 rule, each dearer (the union geometry near grazing): see
// validate/FINDINGS.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

// [lo, hi] mapped from u in [0, 1]: linear, or graded toward one end.
struct GradedInterval {
  double lo, hi;
  int graded = 0;  // -1: toward lo, +1: toward hi, 0: linear
  double x(double u) const {
    if (graded < 0) return lo + (hi - lo) * u * u;
    if (graded > 0) return hi - (hi - lo) * (1 - u) * (1 - u);
    return lo + (hi - lo) * u;
  }
  double dx(double u) const {
    if (graded < 0) return 2 * (hi - lo) * u;
    if (graded > 0) return 2 * (hi - lo) * (1 - u);
    return hi - lo;
  }
};

// [lo, hi] in `parts` equal pieces, split at the kinks inside it; pieces ending at
// a kink graded toward it (both ends: halved, each half toward its end).
std::vector<GradedInterval> graded_pieces(double lo, double hi, const std::vector<double>& kinks, int parts = 1);

// Relative tolerance the cell rule aims at (half of kCellRelTolerance: the rest
// is margin for the error estimate), and its absolute floor (cells at zero).
struct CellRuleTolerance {
  double rel;
  double abs;  // on ∫∫ g, i.e. sr^-1 times the cell's ∫∫ cos sin dtheta dphi
  int max_splits = 200;
};

namespace detail {

struct Rules {
  double x4[4], w4[4], x3[3], w3[3];  // on [0, 1]
  Rules();
};
const Rules& rules();

template <int N, class G>
void product_rules(const G& g, const GradedInterval& t, const GradedInterval& p, double u0, double u1, double v0,
                   double v1, std::array<double, N>& q4, std::array<double, N>& q3) {
  const Rules& r = rules();
  double val[N];
  auto product = [&](const double* x, const double* w, int n, std::array<double, N>& q) {
    q.fill(0);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double u = u0 + (u1 - u0) * x[a], v = v0 + (v1 - v0) * x[b];
        const double wt = w[a] * w[b] * t.dx(u) * p.dx(v);
        g(t.x(u), p.x(v), val);
        for (int k = 0; k < N; ++k) q[k] += wt * val[k];
      }
  };
  product(r.x4, r.w4, 4, q4);
  product(r.x3, r.w3, 3, q3);
  const double area = (u1 - u0) * (v1 - v0);
  for (int k = 0; k < N; ++k) {
    q4[k] *= area;
    q3[k] *= area;
  }
}

template <int N>
struct Piece {
  GradedInterval t, p;
  double u0, u1, v0, v1;
  std::array<double, N> q4, q3;
};

// Global adaptivity: while the summed estimates |Q4 - Q3| exceed tol in some
// component, the piece with the largest estimate (relative to tol) is split: at
// the grazing edge in theta only, 0.15 of it at the edge (a geometric mesh: there
// g ~ (pi/2 - theta)^p with p not an integer, smooth in phi), elsewhere in four.
template <int N, class G>
std::array<double, N> refine(const G& g, std::vector<Piece<N>> pieces, const std::array<double, N>& tol,
                             int max_splits) {
  auto excess = [&](const Piece<N>& pc) {
    double e = 0;
    for (int k = 0; k < N; ++k) e = std::fmax(e, std::fabs(pc.q4[k] - pc.q3[k]) / tol[k]);
    return e;
  };
  for (int split = 0; split < max_splits; ++split) {
    std::array<double, N> err{};
    for (const Piece<N>& pc : pieces)
      for (int k = 0; k < N; ++k) err[k] += std::fabs(pc.q4[k] - pc.q3[k]);
    bool ok = true;
    for (int k = 0; k < N; ++k) ok = ok && err[k] <= tol[k];
    if (ok) break;
    std::size_t worst = 0;
    for (std::size_t j = 1; j < pieces.size(); ++j)
      if (excess(pieces[j]) > excess(pieces[worst])) worst = j;
    const Piece<N> pc = pieces[worst];
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(worst));
    const double um = 0.5 * (pc.u0 + pc.u1), vm = 0.5 * (pc.v0 + pc.v1);
    std::vector<std::array<double, 4>> boxes;
    if (pc.u1 == 1 && pc.t.graded == 0 && std::fabs(pc.t.hi - kPi / 2) < 1e-12) {
      const double ue = pc.u1 - 0.15 * (pc.u1 - pc.u0);
      boxes = {{pc.u0, ue, pc.v0, pc.v1}, {ue, pc.u1, pc.v0, pc.v1}};
    } else {
      boxes = {{pc.u0, um, pc.v0, vm}, {um, pc.u1, pc.v0, vm}, {pc.u0, um, vm, pc.v1}, {um, pc.u1, vm, pc.v1}};
    }
    for (const auto& c : boxes) {
      Piece<N> child{pc.t, pc.p, c[0], c[1], c[2], c[3], {}, {}};
      product_rules<N>(g, pc.t, pc.p, c[0], c[1], c[2], c[3], child.q4, child.q3);
      pieces.push_back(child);
    }
  }
  std::array<double, N> sum{};
  for (const Piece<N>& pc : pieces)
    for (int k = 0; k < N; ++k) sum[k] += pc.q4[k];
  return sum;
}

}  // namespace detail

// ∫∫ g(theta, phi, out) dtheta dphi over [t0, t1] x [p0, p1] (phi relative to phi_i),
// N components, each to tol.rel of its value or tol.abs; theta_parts x phi_parts
// equal pieces to start with (a hemisphere: a few; a table's cell: 1 x 1).
template <int N, class G>
std::array<double, N> cell_rule(const G& g, double theta_i, double t0, double t1, double p0, double p1,
                                const CellRuleTolerance& tol, int theta_parts = 1, int phi_parts = 1) {
  const std::vector<GradedInterval> ts = graded_pieces(t0, t1, {theta_i}, theta_parts);
  std::vector<detail::Piece<N>> pieces;
  std::array<double, N> scale{};
  for (const GradedInterval& t : ts) {
    const bool at_kink = std::fabs(t.lo - theta_i) < 1e-12 || std::fabs(t.hi - theta_i) < 1e-12;
    const std::vector<double> phi_kinks =
        at_kink ? std::vector<double>{-kPi, 0.0, kPi, 2 * kPi} : std::vector<double>{};
    for (const GradedInterval& p : graded_pieces(p0, p1, phi_kinks, phi_parts)) {
      detail::Piece<N> pc{t, p, 0, 1, 0, 1, {}, {}};
      detail::product_rules<N>(g, t, p, 0, 1, 0, 1, pc.q4, pc.q3);
      for (int k = 0; k < N; ++k) scale[k] += std::fabs(pc.q4[k]);
      pieces.push_back(pc);
    }
  }
  std::array<double, N> t;
  for (int k = 0; k < N; ++k) t[k] = std::fmax(tol.rel * scale[k], tol.abs);
  return detail::refine<N>(g, std::move(pieces), t, tol.max_splits);
}

}  // namespace mcref
