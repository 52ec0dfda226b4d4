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
//   |Q4 - Q3| bounds Q4's error, which is far smaller).
// - The piece ending at the grazing edge theta_o = pi/2: there g ~ x^p (a + b x^q ...),
//   x = pi/2 - theta_o, with q not an integer (the G_dist diffuse term: g / x still
//   drifts by ~1-2 % per decade of x at x = 1e-5; the grains' specular lobe peaks at
//   x ~ 1e-3 and vanishes below 1e-4), which no polynomial rule resolves. It takes
//   tanh-sinh in theta_o (exponential convergence for such ends; nested levels give
//   its error estimate; the same end treatment takes a kink at theta_i at its other
//   end) times 4-point Gauss-Legendre in phi.
// While the summed estimates exceed the cell's tolerance, the worst piece is refined
// (global adaptivity), at most max_splits times: the result says whether it met
// the tolerance and the error it reached (validate reports the cells that did not:
// ModelAccuracy, model_evaluation.h). The nodes depend only on the cell and
// theta_i until a check fails, so models of one table share most of them
// (geometry_memo.h).
// Verified against independent references (tests/validate/micrograin/test_brdf_cell_average.cpp).
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

// The rule's estimate, its error bounds (summed over the pieces) and whether
// they met the tolerance before the split limit.
template <int N>
struct CellRuleResult {
  std::array<double, N> value, error;
  // max over components of error / max(scale, abs / rel), scale = the sum of the
  // pieces' |estimates| at the start: on the scale of tol.rel, <= it iff converged.
  double rel_error;
  bool converged;
};

namespace detail {

struct Rules {
  double x4[4], w4[4], x3[3], w3[3];  // on [0, 1]
  Rules();
};
const Rules& rules();

// Tanh-sinh (double exponential) nodes on [0, 1] for a piece ending at the
// grazing edge s = 1 (theta = pi/2), where g ~ x^p (1 + c x^q + ...), x = pi/2 - theta,
// p ≈ 1-2 and q not an integer (validate/FINDINGS.md): s = (1 + tanh(pi/2 sinh t)) / 2,
// t = k h, h = 2^-level. Kept while 1 - s >= 1e-4 (the edge, where g = O(x)) and
// s >= 1e-10 (the smooth end); `even` marks the nodes of level - 1 (nested rules).
struct EdgeNode {
  double s, w;  // node and weight (h ds/dt) on [0, 1]
  bool even;
};
const std::vector<EdgeNode>& edge_nodes(int level);
constexpr int kEdgeLevels = 6;  // levels 3..6 (h = 1/8 .. 1/64)

// g over [0, 1]^2 pieces of the cell in mapped coordinates (u along theta, v along phi).
template <int N>
struct Piece {
  GradedInterval t, p;
  double u0, u1, v0, v1;
  int edge_level;                // 0: Gauss-Legendre in theta; > 0: tanh-sinh at that level
  std::array<double, N> q, err;  // the estimate and its error bound
  double theta_share;            // edge pieces: the share of err from the theta rule
};

template <int N, class G>
void product_rules(const G& g, Piece<N>& pc) {
  const Rules& r = rules();
  double val[N];
  const double du = pc.u1 - pc.u0, dv = pc.v1 - pc.v0;
  auto at = [&](double u, double v, double wt, std::array<double, N>& q) {
    g(pc.t.x(u), pc.p.x(v), val);
    const double w = wt * pc.t.dx(u) * pc.p.dx(v) * du * dv;
    for (int k = 0; k < N; ++k) q[k] += w * val[k];
  };
  std::array<double, N> q4{}, q3{};
  if (pc.edge_level == 0) {
    // 4 x 4 Gauss-Legendre checked against 3 x 3: |Q4 - Q3| bounds Q4's error.
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) at(pc.u0 + du * r.x4[a], pc.v0 + dv * r.x4[b], r.w4[a] * r.w4[b], q4);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) at(pc.u0 + du * r.x3[a], pc.v0 + dv * r.x3[b], r.w3[a] * r.w3[b], q3);
    pc.q = q4;
    for (int k = 0; k < N; ++k) pc.err[k] = std::fabs(q4[k] - q3[k]);
    pc.theta_share = 0;
    return;
  }
  // Edge piece: tanh-sinh in theta x 4-point Gauss-Legendre in phi (Q), against
  // the previous level's nodes (Q', every other node, weights doubled) and, on
  // those, 3 points in phi (Q''). |Q - Q'| bounds Q's theta error (the error of a
  // tanh-sinh level roughly squares at the next, but not before the nodes resolve
  // the grains' specular peak near grazing, so the square is not used); |Q' - Q''|
  // bounds its phi error; the last kept edge term the part beyond 1 - s = 1e-4.
  std::array<double, N> q_prev{}, q_prev3{}, last{};
  const std::vector<EdgeNode>& nodes = edge_nodes(pc.edge_level);
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const EdgeNode& e = nodes[j];
    std::array<double, N> row{};
    for (int b = 0; b < 4; ++b) at(pc.u0 + du * e.s, pc.v0 + dv * r.x4[b], e.w * r.w4[b], row);
    for (int k = 0; k < N; ++k) {
      q4[k] += row[k];
      if (e.even) q_prev[k] += 2 * row[k];
    }
    if (e.even)
      for (int b = 0; b < 3; ++b) at(pc.u0 + du * e.s, pc.v0 + dv * r.x3[b], 2 * e.w * r.w3[b], q_prev3);
    if (j + 1 == nodes.size()) last = row;
  }
  pc.q = q4;
  double theta_err = 0, total = 0;
  for (int k = 0; k < N; ++k) {
    const double d = std::fabs(q4[k] - q_prev[k]);
    const double te = d + std::fabs(last[k]);
    pc.err[k] = te + std::fabs(q_prev[k] - q_prev3[k]);
    theta_err += te;
    total += pc.err[k];
  }
  pc.theta_share = total > 0 ? theta_err / total : 0;
}

// Global adaptivity: while the summed error bounds exceed tol in some component,
// the piece with the largest bound (relative to tol) is refined: a Gauss-Legendre
// piece split in four; an edge piece raised one tanh-sinh level when its theta
// rule dominates its bound (at most kEdgeLevels), else halved in phi.
// Returns the sums and, in rel_error, max over components of err / tol (the caller scales it).
template <int N, class G>
CellRuleResult<N> refine(const G& g, std::vector<Piece<N>> pieces, const std::array<double, N>& tol, int max_splits) {
  auto excess = [&](const Piece<N>& pc) {
    double e = 0;
    for (int k = 0; k < N; ++k) e = std::fmax(e, pc.err[k] / tol[k]);
    return e;
  };
  for (int split = 0;; ++split) {
    std::array<double, N> err{};
    for (const Piece<N>& pc : pieces)
      for (int k = 0; k < N; ++k) err[k] += pc.err[k];
    bool ok = true;
    for (int k = 0; k < N; ++k) ok = ok && err[k] <= tol[k];
    if (ok || split == max_splits) {
      CellRuleResult<N> r{{}, err, 0, ok};
      for (int k = 0; k < N; ++k) r.rel_error = std::fmax(r.rel_error, err[k] / tol[k]);
      for (const Piece<N>& pc : pieces)
        for (int k = 0; k < N; ++k) r.value[k] += pc.q[k];
      return r;
    }
    std::size_t worst = 0;
    for (std::size_t j = 1; j < pieces.size(); ++j)
      if (excess(pieces[j]) > excess(pieces[worst])) worst = j;
    const Piece<N> pc = pieces[worst];
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(worst));
    const double um = 0.5 * (pc.u0 + pc.u1), vm = 0.5 * (pc.v0 + pc.v1);
    std::vector<Piece<N>> children;
    if (pc.edge_level > 0 && pc.theta_share > 0.5 && pc.edge_level < kEdgeLevels) {
      children = {pc};
      ++children[0].edge_level;
    } else if (pc.edge_level > 0) {
      children = {pc, pc};
      children[0].v1 = children[1].v0 = vm;
    } else {
      children.assign(4, pc);
      children[0].u1 = children[1].u0 = children[2].u1 = children[3].u0 = um;
      children[0].v1 = children[1].v1 = children[2].v0 = children[3].v0 = vm;
    }
    for (Piece<N>& c : children) {
      product_rules<N>(g, c);
      pieces.push_back(c);
    }
  }
}

}  // namespace detail

// ∫∫ g(theta, phi, out) dtheta dphi over [t0, t1] x [p0, p1] (phi relative to phi_i),
// N components, each to tol.rel of its value or tol.abs; theta_parts x phi_parts
// equal pieces to start with (a hemisphere: a few; a table's cell: 1 x 1).
template <int N, class G>
CellRuleResult<N> cell_rule(const G& g, double theta_i, double t0, double t1, double p0, double p1,
                            const CellRuleTolerance& tol, int theta_parts = 1, int phi_parts = 1) {
  const std::vector<GradedInterval> ts = graded_pieces(t0, t1, {theta_i}, theta_parts);
  std::vector<detail::Piece<N>> pieces;
  std::array<double, N> scale{};
  for (GradedInterval t : ts) {
    // The piece at the grazing edge: tanh-sinh in theta, which also takes a kink at its other end.
    const bool edge = std::fabs(t.hi - kPi / 2) < 1e-12;
    if (edge) t.graded = 0;
    const bool at_kink = std::fabs(t.lo - theta_i) < 1e-12 || std::fabs(t.hi - theta_i) < 1e-12;
    const std::vector<double> phi_kinks =
        at_kink ? std::vector<double>{-kPi, 0.0, kPi, 2 * kPi} : std::vector<double>{};
    for (const GradedInterval& p : graded_pieces(p0, p1, phi_kinks, phi_parts)) {
      detail::Piece<N> pc{t, p, 0, 1, 0, 1, edge ? 3 : 0, {}, {}, 0};
      detail::product_rules<N>(g, pc);
      for (int k = 0; k < N; ++k) scale[k] += std::fabs(pc.q[k]);
      pieces.push_back(pc);
    }
  }
  std::array<double, N> t;
  for (int k = 0; k < N; ++k) t[k] = std::fmax(tol.rel * scale[k], tol.abs);
  CellRuleResult<N> r = detail::refine<N>(g, std::move(pieces), t, tol.max_splits);
  r.rel_error *= tol.rel;  // err / t = (err / max(scale, abs / rel)) / rel
  return r;
}

}  // namespace mcref
