#pragma once
// Each layer's density (rho profile(depth), or density_vdb's voxels, sim/slab/density_vdb.h)
// in an openvdb::FloatGrid: a periodic lateral tile of
// side `tile` (lateral_voxels per side) voxelised in depth (depth_voxels
// intervals), node-centred so the layer faces lie on voxel planes and the
// trilinear (BoxSampler) reconstruction of a linear depth profile is exact.
// Index (i, j, k): x = i h_x, y = j h_y, k = 0 at the layer's bottom face,
// k = depth_voxels at its top; world z = -depth (the top face of the stack at z = 0).
// The column i = N (j = N) repeats i = 0 (j = 0), so lookups wrap periodically.
//
// SGGX layers also hold their matrix field S(x) on the same voxels, as two
// openvdb::Vec3DGrid (double, so that small alpha keeps S positive definite):
//   "layer<k>_S_diag"    = (S_xx, S_yy, S_zz)
//   "layer<k>_S_offdiag" = (S_xy, S_xz, S_yz)
// filled from the layer's alpha and omega_p (surface_like / fiber_like). The
// field between voxels is the trilinear (BoxSampler) interpolation of each
// component, a convex combination of positive definite matrices, hence
// positive definite. Since sigma(w; sum_i w_i S_i) = sqrt(sum_i w_i w^T S_i w)
// <= max_i sqrt(lambda_max(S_i)), max_sigma(k) (the largest sqrt(lambda_max)
// over the voxels) bounds sigma(w; S(x)) for every w and x, and
// max_density(k) * max_sigma(k) is a direction-free majorant of
// rho(x) sigma(w; S(x)). (The maximum over voxels of the product rho sqrt(lambda_max)
// would not bound the product of two interpolated fields.)
#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "models/sggx/mat3.h"
#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

class DensityGrids {
 public:
  explicit DensityGrids(const SlabGeometry& geometry);
  // Density grids, one per layer.
  const std::vector<openvdb::FloatGrid::Ptr>& grids() const { return grids_; }
  // Every grid (per layer: density, then S_diag and S_offdiag for SGGX layers).
  openvdb::GridPtrVec all_grids() const;
  // SGGX matrix grids of layer k (null for non-SGGX layers).
  bool has_sggx(std::size_t k) const { return static_cast<bool>(s_diag_[k]); }
  const openvdb::Vec3DGrid::Ptr& s_diag(std::size_t k) const { return s_diag_[k]; }
  const openvdb::Vec3DGrid::Ptr& s_offdiag(std::size_t k) const { return s_offdiag_[k]; }
  // Largest sqrt(lambda_max(S)) over the voxels of layer k (1 for non-SGGX layers).
  double max_sigma(std::size_t k) const { return max_sigma_[k]; }
  // Largest voxel value of layer k (a majorant of the trilinear field).
  double max_density(std::size_t k) const { return max_[k]; }
  // Optical thickness of layer k along the normal, integrating the trilinear
  // field of one column (trapezoids between the voxel planes).
  double column_optical_thickness(std::size_t k) const;
  const SlabGeometry& geometry() const { return geometry_; }

 private:
  friend class GridLookup;
  SlabGeometry geometry_;
  std::vector<openvdb::FloatGrid::Ptr> grids_;
  std::vector<openvdb::Vec3DGrid::Ptr> s_diag_, s_offdiag_;
  std::vector<double> max_sigma_;
  std::vector<double> max_, top_, bottom_, hz_;
  double hx_ = 1;
  int n_lateral_ = 1;
};

// Per-thread lookups through OpenVDB value accessors and the trilinear sampler.
class GridLookup {
 public:
  explicit GridLookup(const DensityGrids& g);
  double density(int layer, double x, double y, double depth);
  // The SGGX matrix at a point of an SGGX layer (trilinear per component).
  sggx::Mat3 sggx_matrix(int layer, double x, double y, double depth);
  // Both at once (one index-space transform).
  double density_and_sggx(int layer, double x, double y, double depth, sggx::Mat3& s);

 private:
  openvdb::Vec3R index(int layer, double x, double y, double depth) const;
  sggx::Mat3 matrix_at(int layer, const openvdb::Vec3R& ijk);
  const DensityGrids& g_;
  std::vector<openvdb::FloatGrid::ConstAccessor> acc_;
  std::vector<std::unique_ptr<openvdb::Vec3DGrid::ConstAccessor>> diag_, off_;  // null: no S
};

// Largest eigenvalue of a symmetric 3x3 matrix (Jacobi rotations).
double largest_eigenvalue(const sggx::Mat3& s);

}  // namespace mcref::volume
