#include "sim/slab/medium.h"

#include "sim/slab/density_grid.h"
#include "sim/slab/voxel_density.h"

namespace mcref::volume {

SlabMedium::SlabMedium(const SlabGeometry& g)
    : SlabMedium(g, g.grid.openvdb ? std::make_unique<DensityGrids>(g) : nullptr) {}

SlabMedium::SlabMedium(const SlabGeometry& g, std::unique_ptr<DensityGrids> grids, int lateral_block, int reach,
                       bool depth_profiles)
    : geometry_(g), grids_(std::move(grids)) {
  double top = 0;
  for (const SlabLayer& l : g.layers) {
    MediumLayer m;
    m.top = top;
    m.bottom = top + l.thickness;
    m.density = l.density;
    m.phase = make_phase(l);
    layers_.push_back(std::move(m));
    top += l.thickness;
  }
  if (grids_) {
    majorants_ = build_majorants(*grids_, lateral_block, reach);
    voxels_ = std::make_unique<VoxelDensity>(*grids_);
    cell_bounds_ = flatten_cell_bounds(majorants_, g.grid.depth_voxels);
    for (std::size_t k = 0; k < majorants_.size(); ++k)
      depth_profiles_.push_back(majorants_[k].s_varies || !depth_profiles ? std::nullopt
                                                                           : voxels_->depth_profile(static_cast<int>(k)));
  }
}

SlabMedium::~SlabMedium() = default;

}  // namespace mcref::volume
