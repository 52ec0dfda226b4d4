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

 private:
  double top_, bottom_, hz_, inv_hz_;
  std::vector<double> rho_;
  std::vector<double> column_;  // per plane: the integral of rho from plane 0, in index units (rho x planes)
  // The interval holding column value i * column_.back() / interval_of_.size() (for invert()).
  std::vector<int> interval_of_;
  double inv_column_step_ = 0;
  double index(double depth) const;  // (bottom - depth) / hz in [0, planes - 1]
  // The index u where the column reaches g (column_[0] <= g <= column_.back()).
  double invert(double g) const;
};

}  // namespace mcref::volume
