#include "sim/slab/voxel_density.h"

namespace mcref::volume {

VoxelDensity::VoxelDensity(const DensityGrids& g) {
  const SlabGeometry& geo = g.geometry();
  const int n = geo.grid.lateral_voxels, nz = geo.grid.depth_voxels;
  inv_hx_ = n / geo.grid.tile;
  n_ = n;
  inv_n_ = 1.0 / n;
  nz_ = nz;
  planes_ = n + 1;
  depth_planes_ = nz + 2;
  double top = 0;
  for (std::size_t k = 0; k < g.grids().size(); ++k) {
    Layer l;
    l.top = top;
    l.bottom = top + geo.layers[k].thickness;
    l.inv_hz = nz / geo.layers[k].thickness;
    top = l.bottom;
    auto acc = g.grids()[k]->getConstAccessor();
    l.values.resize(static_cast<std::size_t>(planes_ * planes_ * depth_planes_));
    for (int i = 0; i < planes_; ++i)
      for (int j = 0; j < planes_; ++j)
        for (int z = 0; z < depth_planes_; ++z)
          l.values[static_cast<std::size_t>((i * planes_ + j) * depth_planes_ + z)] = acc.getValue(openvdb::Coord(i, j, z));
    layers_.push_back(std::move(l));
  }
}

std::optional<DepthProfile> VoxelDensity::depth_profile(int k) const {
  const Layer& l = layers_[static_cast<std::size_t>(k)];
  const std::ptrdiff_t column = depth_planes_;  // values per column, column (0, 0) first
  for (std::ptrdiff_t c = 1; c < planes_ * planes_; ++c)
    if (!std::equal(l.values.begin(), l.values.begin() + column, l.values.begin() + c * column)) return std::nullopt;
  // Planes 0 (bottom face) ... depth voxels (top face); the last stored one is read with weight 0.
  return DepthProfile(l.top, l.bottom, std::vector<double>(l.values.begin(), l.values.begin() + column - 1));
}

}  // namespace mcref::volume
