#include "sim/tally/polar_bins.h"

#include <cstdint>
#include <cstring>
#include <limits>

namespace mcref {

namespace {
// Doubles in [-1, 1] as integers of the same order (and back).
std::int64_t key_of(double x) {
  std::int64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b >= 0 ? b : -(b & INT64_MAX);
}
double double_of(std::int64_t k) {
  const std::int64_t b = k >= 0 ? k : (-k | INT64_MIN);
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}
}  // namespace

PolarBins::PolarBins(const Axis& theta) : edges_(static_cast<int>(theta.values.size())) {
  // w_j by bisection over the doubles of [-1, 1]: theta >= e_j holds at lo, not at hi.
  w_.push_back(std::numeric_limits<double>::infinity());
  for (double e : theta.values) {
    auto at_or_past = [&](double z) { return spherical_theta({0, 0, z}) >= e; };
    if (!at_or_past(-1)) {
      w_.push_back(-2);  // no z: theta never reaches e
      continue;
    }
    if (at_or_past(1)) {
      w_.push_back(1);  // every z
      continue;
    }
    std::int64_t lo = key_of(-1), hi = key_of(1);
    while (hi - lo > 1) {
      const std::int64_t mid = lo + (hi - lo) / 2;
      (at_or_past(double_of(mid)) ? lo : hi) = mid;
    }
    w_.push_back(double_of(lo));
  }
  w_.push_back(-std::numeric_limits<double>::infinity());
  // First guesses: the count at the start of each cell of sqrt(1 - z), 16
  // cells per edge, so that few guesses need a correction.
  cells_ = 16 * edges_;
  scale_ = static_cast<float>(cells_ / std::sqrt(2.0));
  for (int k = 0; k <= cells_; ++k) {
    const double s = k / static_cast<double>(scale_), z = 1 - s * s;
    int c = 0;
    while (z <= w_[c + 1]) ++c;
    guess_.push_back(c);
  }
}

}  // namespace mcref
