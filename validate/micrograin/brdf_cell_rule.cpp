#include "validate/micrograin/brdf_cell_rule.h"

#include <array>
#include <cmath>

#include "models/core/quadrature.h"

namespace mcref {

std::vector<GradedInterval> graded_pieces(double lo, double hi, const std::vector<double>& kinks, int parts) {
  constexpr double eps = 1e-12;
  auto is_kink = [&](double x) {
    for (double k : kinks)
      if (std::fabs(x - k) < eps) return true;
    return false;
  };
  std::vector<double> cuts;
  for (int j = 0; j <= parts; ++j) cuts.push_back(j == parts ? hi : lo + (hi - lo) * j / parts);
  for (double k : kinks)
    if (k > lo + eps && k < hi - eps) cuts.push_back(k);
  std::sort(cuts.begin(), cuts.end());
  std::vector<GradedInterval> out;
  for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
    const double a = cuts[j], b = cuts[j + 1];
    if (b - a < eps) continue;
    const bool ka = is_kink(a), kb = is_kink(b);
    if (ka && kb) {
      const double m = 0.5 * (a + b);
      out.push_back({a, m, -1});
      out.push_back({m, b, +1});
    } else {
      out.push_back({a, b, ka ? -1 : kb ? +1 : 0});
    }
  }
  return out;
}

namespace detail {

Rules::Rules() {
  const GaussLegendre g4(4), g3(3);
  for (int k = 0; k < 4; ++k) {
    x4[k] = 0.5 * (1 + g4.x[k]);
    w4[k] = 0.5 * g4.w[k];
  }
  for (int k = 0; k < 3; ++k) {
    x3[k] = 0.5 * (1 + g3.x[k]);
    w3[k] = 0.5 * g3.w[k];
  }
}

const std::vector<EdgeNode>& edge_nodes(int level) {
  static const std::array<std::vector<EdgeNode>, kEdgeLevels + 1> levels = [] {
    std::array<std::vector<EdgeNode>, kEdgeLevels + 1> out;
    for (int l = 1; l <= kEdgeLevels; ++l) {
      const double h = std::ldexp(1.0, -l);
      for (int k = -(64 << l); k <= (64 << l); ++k) {
        const double t = k * h, a = 0.5 * kPi * std::sinh(t), e = std::exp(-2 * std::fabs(a));
        const double near = e / (1 + e);  // distance of s to the nearer end, accurately
        const double s = t < 0 ? near : 1 - near;
        if (near < (t < 0 ? 1e-10 : 1e-4)) continue;
        const double w = h * 0.25 * kPi * std::cosh(t) * 4 * e / ((1 + e) * (1 + e));  // h ds/dt
        out[l].push_back({s, w, k % 2 == 0});
      }
    }
    return out;
  }();
  return levels[level];
}

const Rules& rules() {
  static const Rules r;
  return r;
}

}  // namespace detail

}  // namespace mcref
