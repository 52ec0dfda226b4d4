#pragma once
// Bin of the polar angle theta = acos(z) of a unit direction on a theta axis,
// found from z = cos(theta) without acos: a table indexed by sqrt(1 - z)
// (about linear in theta) gives a first bin, and comparisons of z with the
// edges' thresholds correct it. The thresholds are the doubles at which
// axis.find_bin(spherical_theta) changes, found once by bisection over the
// doubles, so the bin is exactly acos's as long as acos is monotone (tested:
// tests/sim/tally/test_polar_bins.cpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/vec.h"
#include "sim/tally/table.h"

namespace mcref {

class PolarBins {
 public:
  explicit PolarBins(const Axis& theta);

  // == theta.find_bin(spherical_theta({0, 0, z})): the bin, or -1 outside the axis.
  int bin(double z) const {
    z = std::fmin(1.0, std::fmax(-1.0, z));  // as spherical_theta (NaN -> -1)
    const float s = std::sqrt(static_cast<float>(1 - z));  // in [0, sqrt 2]; a guess only
    int c = guess_[std::min(static_cast<int>(s * scale_), cells_)];
    // c := the number of edges e_j with theta >= e_j, i.e. of thresholds z <= w_j.
    while (z > w_[c]) --c;
    while (z <= w_[c + 1]) ++c;
    return c >= 1 && c < edges_ ? c - 1 : -1;
  }

 private:
  int edges_;               // edges of the axis (bins + 1)
  // w_[j + 1]: the largest z with acos(z) >= e_j (decreasing in j), between
  // the sentinels w_[0] = +inf and w_[edges + 1] = -inf.
  std::vector<double> w_;
  float scale_;             // table cells per unit of sqrt(1 - z)
  int cells_;               // cells up to sqrt 2
  std::vector<int> guess_;  // the count at the start of each cell, cells_ + 1 of them
};

}  // namespace mcref
