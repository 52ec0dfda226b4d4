#pragma once
// The transport view of a slab: per layer its depth range, density majorant
// and phase function; the substrate; optional OpenVDB density grids.
// Depth is measured downward from the top face (z = -depth).
#include <memory>
#include <vector>

#include "sim/slab/phase.h"
#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

class DensityGrids;

struct MediumLayer {
  double top = 0, bottom = 0;  // depths of the faces
  double density = 0;          // homogeneous density (constant profile)
  double majorant = 0;         // max density over the layer (delta tracking)
  // OpenVDB path, SGGX layers: S(x) read from the grids; delta tracking against
  // the direction-free majorant max rho * max sqrt(lambda_max(S)) (density_grid.h).
  bool sggx_grid = false;
  double extinction_majorant = 0;
  std::unique_ptr<PhaseFunction> phase;
};

class SlabMedium {
 public:
  // Builds the OpenVDB grids too when geometry.grid.openvdb is set.
  explicit SlabMedium(const SlabGeometry& geometry);
  ~SlabMedium();
  const SlabGeometry& geometry() const { return geometry_; }
  const std::vector<MediumLayer>& layers() const { return layers_; }
  const SlabSubstrate& substrate() const { return geometry_.substrate; }
  bool has_substrate() const { return geometry_.substrate.kind != SlabSubstrate::Kind::kNone; }
  double bottom() const { return layers_.back().bottom; }
  const DensityGrids* grids() const { return grids_.get(); }

 private:
  SlabGeometry geometry_;
  std::vector<MediumLayer> layers_;
  std::unique_ptr<DensityGrids> grids_;
};

}  // namespace mcref::volume
