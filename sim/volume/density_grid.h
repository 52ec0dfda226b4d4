#pragma once
// Each layer's density in an openvdb::FloatGrid: a periodic lateral tile of
// side `tile` (lateral_voxels per side) voxelised in depth (depth_voxels
// intervals), node-centred so the layer faces lie on voxel planes and the
// trilinear (BoxSampler) reconstruction of a linear depth profile is exact.
// Index (i, j, k): x = i h_x, y = j h_y, k = 0 at the layer's bottom face,
// k = depth_voxels at its top; world z = -depth (the top face of the stack at z = 0).
// The column i = N (j = N) repeats i = 0 (j = 0), so lookups wrap periodically.
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "sim/geometry/slab.h"

namespace mcref::volume {

class DensityGrids {
 public:
  explicit DensityGrids(const SlabGeometry& geometry);
  const std::vector<openvdb::FloatGrid::Ptr>& grids() const { return grids_; }
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
  std::vector<double> max_, top_, bottom_, hz_;
  double hx_ = 1;
  int n_lateral_ = 1;
};

// Per-thread lookups through OpenVDB value accessors and the trilinear sampler.
class GridLookup {
 public:
  explicit GridLookup(const DensityGrids& g);
  double density(int layer, double x, double y, double depth);

 private:
  const DensityGrids& g_;
  std::vector<openvdb::FloatGrid::ConstAccessor> acc_;
};

// Writes the grids (names "layer<k>_density", with the layer's parameters as
// grid metadata) to a .vdb file.
void write_vdb(const std::string& path, const DensityGrids& grids);

}  // namespace mcref::volume
