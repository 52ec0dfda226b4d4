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

double DepthProfile::index(double depth) const {
  return std::min(static_cast<double>(rho_.size() - 1), std::max(0.0, (bottom_ - depth) * inv_hz_));
}

double DepthProfile::density(double depth) const {
  const double u = index(depth);
  const std::size_t k = std::min(static_cast<std::size_t>(u), rho_.size() - 2);
  return rho_[k] + (rho_[k + 1] - rho_[k]) * (u - static_cast<double>(k));
}

// In interval k, rho = rho_k + s t (t = u - k in [0, 1], s = rho_k+1 - rho_k), so
// the column from plane k is rho_k t + s t^2 / 2 = R: t = 2 R / (rho_k + sqrt(rho_k^2 + 2 s R))
// (the root in [0, 1]; this form has no cancellation).
double DepthProfile::invert(double g) const {
  const std::size_t last = rho_.size() - 2;
  // The interval: from the table's guess (the interval of a column value at most g), onwards.
  std::size_t k = static_cast<std::size_t>(interval_of_[std::min(interval_of_.size() - 1, static_cast<std::size_t>(g * inv_column_step_))]);
  k += k < last && column_[k + 1] <= g;  // usually enough (no branch)
  while (k < last && column_[k + 1] <= g) ++k;  // thin intervals
  const double r = std::max(0.0, g - column_[k]), a = rho_[k], s = rho_[k + 1] - rho_[k];
  const double denom = a + std::sqrt(std::max(0.0, a * a + 2 * s * r));
  const double t = denom > 0 ? std::min(1.0, 2 * r / denom) : 0.0;
  return static_cast<double>(k) + t;
}

double DepthProfile::travel(double depth, bool down, double& amount) const {
  const double u0 = index(depth);
  const std::size_t k = std::min(static_cast<std::size_t>(u0), rho_.size() - 2);
  const double t = u0 - static_cast<double>(k);
  const double g0 = column_[k] + (rho_[k] + 0.5 * (rho_[k + 1] - rho_[k]) * t) * t;  // the column up to u0
  const double need = amount * inv_hz_;
  // Deeper is towards plane 0 (the column decreasing), shallower towards the top plane.
  const double g = down ? g0 - need : g0 + need;
  if (down ? !(g > 0) : !(g < column_.back())) {
    amount = (need - (down ? g0 : column_.back() - g0)) * hz_;
    return down ? bottom_ : top_;
  }
  amount = 0;
  return bottom_ - invert(g) * hz_;
}

}  // namespace mcref::volume
