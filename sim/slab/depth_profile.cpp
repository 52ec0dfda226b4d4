#include "sim/slab/depth_profile.h"

#include <algorithm>
#include <cmath>

namespace mcref::volume {

DepthProfile::DepthProfile(double top, double bottom, std::vector<double> rho)
    : top_(top), bottom_(bottom), rho_(std::move(rho)) {
  const double n = static_cast<double>(rho_.size() - 1);
  hz_ = (bottom - top) / n;
  inv_hz_ = n / (bottom - top);
  column_.assign(rho_.size(), 0.0);
  for (std::size_t k = 1; k < rho_.size(); ++k) column_[k] = column_[k - 1] + 0.5 * (rho_[k - 1] + rho_[k]);
  // invert()'s first guess: 4 entries per interval, equally spaced in the column.
  const std::size_t entries = 4 * (rho_.size() - 1);
  const int last = static_cast<int>(rho_.size()) - 2;
  interval_of_.assign(entries, 0);
  if (!(column_.back() > 0)) return;
  inv_column_step_ = static_cast<double>(entries) / column_.back();
  for (std::size_t i = 0, k = 0; i < entries; ++i) {
    const double g = static_cast<double>(i) / inv_column_step_;
    while (static_cast<int>(k) < last && column_[k + 1] <= g) ++k;
    interval_of_[i] = static_cast<int>(k);
  }
}

}  // namespace mcref::volume
