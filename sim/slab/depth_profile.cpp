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
  const std::size_t k = std::min(last, static_cast<std::size_t>(std::upper_bound(column_.begin() + 1, column_.end(), g) - (column_.begin() + 1)));
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
