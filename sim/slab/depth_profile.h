#pragma once
// Exact free flights through an OpenVDB layer whose density varies in depth
// only (every slab a TOML describes: a constant, linear or tabulated profile).
// The voxels' trilinear reconstruction (sim/slab/voxel_density.h) is then, at
// any lateral position, linear in depth between voxel planes, so the optical
// depth along a ray, sigma(w) / |w_z| times the column integral of rho over
// depth, is piecewise quadratic: a flight inverts it (one search and one
// quadratic per flight) instead of delta tracking, with no null collisions and
// no voxel lookups (issue #21). sim/slab/free_flight.cpp uses it for layers
// with one SGGX matrix (or a non-SGGX phase function); VoxelDensity::
// depth_profile tells which layers have one.
#include <algorithm>
#include <cmath>
#include <vector>

namespace mcref::volume {

class DepthProfile {
 public:
  // rho at the layer's voxel planes, plane 0 on its bottom face and plane
  // rho.size() - 1 on its top face, linear in between.
  DepthProfile(double top, double bottom, std::vector<double> rho);

  double density(double depth) const;
  // From `depth` deeper (down) or shallower: the depth at which the column
  // integral of rho reaches `amount` (in density x depth). If a face of the
  // layer comes first, returns that face's depth and leaves in `amount` what
  // is still to go; otherwise sets `amount` to 0.
  double travel(double depth, bool down, double& amount) const;
  // The column integral of rho from `depth` to the bottom face (down) or the
  // top face (in density x depth): the optical depth to that face along w is
  // sigma(w) / |w_z| times it (the next-event estimators, sim/slab/escape.h).
  double column_to_face(double depth, bool down) const;

  // The tables travel() reads, for the data-parallel walk's own flights
  // (sim/slab/wave_grid_flights.cpp): rho and the column per plane, and the first-guess
  // interval per column step (column value i / inv_column_step()).
  const std::vector<double>& rho() const { return rho_; }
  const std::vector<double>& column() const { return column_; }
  const std::vector<int>& interval_of() const { return interval_of_; }
  double inv_column_step() const { return inv_column_step_; }
  double hz() const { return hz_; }  // depth per interval
  double inv_hz() const { return inv_hz_; }

 private:
  double top_, bottom_, hz_, inv_hz_;
  std::vector<double> rho_;
  std::vector<double> column_;  // per plane: the integral of rho from plane 0, in index units (rho x planes)
  // The interval holding column value i * column_.back() / interval_of_.size() (for invert()).
  std::vector<int> interval_of_;
  double inv_column_step_ = 0;
  double index(double depth) const;  // (bottom - depth) / hz in [0, planes - 1]
  double column_up_to(double u) const;  // the column from plane 0 to index u, in index units
  // The index u where the column reaches g (column_[0] <= g <= column_.back()).
  double invert(double g) const;
};

// (Inline: a flight's cost depends on these being inlined into it.)
inline double DepthProfile::index(double depth) const {
  return std::min(static_cast<double>(rho_.size() - 1), std::max(0.0, (bottom_ - depth) * inv_hz_));
}

inline double DepthProfile::density(double depth) const {
  const double u = index(depth);
  const std::size_t k = std::min(static_cast<std::size_t>(u), rho_.size() - 2);
  return rho_[k] + (rho_[k + 1] - rho_[k]) * (u - static_cast<double>(k));
}

// In interval k, rho = rho_k + s t (t = u - k in [0, 1], s = rho_k+1 - rho_k), so
// the column from plane k is rho_k t + s t^2 / 2 = R: t = 2 R / (rho_k + sqrt(rho_k^2 + 2 s R))
// (the root in [0, 1]; this form has no cancellation).
inline double DepthProfile::invert(double g) const {
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

inline double DepthProfile::column_up_to(double u) const {
  const std::size_t k = std::min(static_cast<std::size_t>(u), rho_.size() - 2);
  const double t = u - static_cast<double>(k);
  return column_[k] + (rho_[k] + 0.5 * (rho_[k + 1] - rho_[k]) * t) * t;
}

inline double DepthProfile::column_to_face(double depth, bool down) const {
  const double g0 = column_up_to(index(depth));
  return std::max(0.0, down ? g0 : column_.back() - g0) * hz_;  // (on the top face: -1 ulp at most)
}

inline double DepthProfile::travel(double depth, bool down, double& amount) const {
  const double g0 = column_up_to(index(depth));
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
