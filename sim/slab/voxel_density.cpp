#include "sim/slab/voxel_density.h"

namespace mcref::volume {

VoxelDensity::VoxelDensity(const DensityGrids& g) : grids_(g) {
  const SlabGeometry& geo = g.geometry();
  nx_ = geo.grid.lateral_voxels + 2;
  nz_ = geo.grid.depth_voxels + 2;
  for (const openvdb::FloatGrid::Ptr& grid : g.grids()) {
    auto acc = grid->getConstAccessor();
    std::vector<float> v(static_cast<std::size_t>(nx_) * nx_ * nz_);
    for (int i = 0; i < nx_; ++i)
      for (int j = 0; j < nx_; ++j)
        for (int k = 0; k < nz_; ++k)
          v[(static_cast<std::size_t>(i) * nx_ + j) * nz_ + k] = acc.getValue(openvdb::Coord(i, j, k));
    values_.push_back(std::move(v));
  }
}

}  // namespace mcref::volume
