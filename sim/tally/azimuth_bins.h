#pragma once
// Bin of the relative azimuth phi_o - phi_ref of a direction, uniform bins
// over [0, 2pi) (or [0, pi] folded: |phi_o - phi_ref|), without atan2: the
// direction is rotated by -phi_ref, a cheap approximate angle (error < 0.005
// rad) gives a first bin, and sign tests against the exact bin-edge unit
// vectors correct it. The bin is the one of the exact angle, up to rounding
// exactly at an edge.
#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

class AzimuthBins {
 public:
  AzimuthBins(int bins, double phi_ref, bool folded)
      : bins_(bins), folded_(folded), cos_ref_(std::cos(phi_ref)), sin_ref_(std::sin(phi_ref)) {
    const double span = folded ? kPi : 2 * kPi;
    scale_ = bins / span;
    for (int k = 0; k <= bins; ++k) {
      edge_cos_.push_back(std::cos(k * span / bins));
      edge_sin_.push_back(std::sin(k * span / bins));
    }
  }

  // Bin in [0, bins) of the azimuth of w (w.z is ignored).
  int bin(Vec3 w) const {
    const double x = w.x * cos_ref_ + w.y * sin_ref_;
    double y = w.y * cos_ref_ - w.x * sin_ref_;
    if (folded_) y = std::fabs(y);
    int p = std::clamp(static_cast<int>(approximate_angle(x, y) * scale_), 0, bins_ - 1);
    // Edge k lies before (x, y) iff cross(edge_k, (x, y)) >= 0, for edges within pi of it.
    while (p > 0 && edge_cos_[p] * y - edge_sin_[p] * x < 0) --p;
    while (p < bins_ - 1 && edge_cos_[p + 1] * y - edge_sin_[p + 1] * x > 0) ++p;
    return p;
  }

 private:
  // atan2(y, x) in [0, 2pi) to within 0.005 rad (0 for the zero vector).
  static double approximate_angle(double x, double y) {
    const double ax = std::fabs(x), ay = std::fabs(y);
    const double hi = std::max(ax, ay);
    const double t = hi > 0 ? std::min(ax, ay) / hi : 0;
    const double a = t * (0.25 * kPi + 0.273 * (1 - t));  // atan(t) on [0, 1]
    // The octant's reflections by copysign, not by branches on the (random)
    // signs: a -> pi/2 - a if ay > ax, then pi - a if x < 0, then 2pi - a if
    // y < 0. (Adding +0 turns -0 into +0, which must count as positive.)
    const double b = 0.25 * kPi - std::copysign(0.25 * kPi - a, ax - ay);
    const double c = 0.5 * kPi - std::copysign(0.5 * kPi - b, x + 0.0);
    return kPi - std::copysign(kPi - c, y + 0.0);
  }

  int bins_;
  bool folded_;
  double cos_ref_, sin_ref_, scale_;
  std::vector<double> edge_cos_, edge_sin_;  // unit vectors of the bin edges k span / bins
};

}  // namespace mcref
