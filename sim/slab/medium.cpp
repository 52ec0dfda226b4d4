#include "sim/slab/medium.h"

#include "sim/slab/density_grid.h"

namespace mcref::volume {

SlabMedium::SlabMedium(const SlabGeometry& g) : geometry_(g) {
  double top = 0;
  for (const SlabLayer& l : g.layers) {
    MediumLayer m;
    m.top = top;
    m.bottom = top + l.thickness;
    m.density = l.density;
    m.majorant = l.density * l.profile.max();
    m.phase = make_phase(l);
    layers_.push_back(std::move(m));
    top += l.thickness;
  }
  if (g.grid.openvdb) {
    grids_ = std::make_unique<DensityGrids>(g);
    for (std::size_t k = 0; k < layers_.size(); ++k) {
      layers_[k].majorant = grids_->max_density(k);
      layers_[k].sggx_grid = grids_->has_sggx(k);
      layers_[k].extinction_majorant = grids_->max_density(k) * grids_->max_sigma(k);
    }
  }
}

SlabMedium::~SlabMedium() = default;

}  // namespace mcref::volume
