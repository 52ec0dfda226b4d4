#pragma once
// The transport view of a slab: per layer its depth range, density and phase
// function; the substrate; optional OpenVDB density grids with their per-cell
// majorants (sim/slab/majorant_grid.h) and, for layers varying in depth only,
// their profiles (sim/slab/depth_profile.h).
// Depth is measured downward from the top face (z = -depth).
#include <memory>
#include <optional>
#include <vector>

#include "sim/slab/cell_bounds.h"
#include "sim/slab/depth_profile.h"
#include "sim/slab/majorant_grid.h"
#include "sim/slab/phase.h"
#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

class DensityGrids;
class VoxelDensity;

struct MediumLayer {
  double top = 0, bottom = 0;  // depths of the faces
  double density = 0;          // homogeneous density (constant profile)
  std::unique_ptr<PhaseFunction> phase;
};

class SlabMedium {
 public:
  // Builds the OpenVDB grids too when geometry.grid.openvdb is set.
  explicit SlabMedium(const SlabGeometry& geometry);
  // Over given grids of that geometry (e.g. with voxels edited after
  // DensityGrids built them); the majorants are read from the grids' voxels
  // (lateral_block, reach: see build_majorants); depth_profiles = false: no
  // exact flights, every layer delta-tracked (for tests).
  SlabMedium(const SlabGeometry& geometry, std::unique_ptr<DensityGrids> grids, int lateral_block = 0, int reach = 0,
             bool depth_profiles = true);
  ~SlabMedium();
  const SlabGeometry& geometry() const { return geometry_; }
  const std::vector<MediumLayer>& layers() const { return layers_; }
  const SlabSubstrate& substrate() const { return geometry_.substrate; }
  bool has_substrate() const { return geometry_.substrate.kind != SlabSubstrate::Kind::kNone; }
  double bottom() const { return layers_.back().bottom; }
  const DensityGrids* grids() const { return grids_.get(); }
  // Per layer (OpenVDB grids only).
  const std::vector<LayerMajorants>& majorants() const { return majorants_; }
  // Dense copy of the density voxels for the lookups (OpenVDB grids only).
  const VoxelDensity* voxels() const { return voxels_.get(); }
  // The majorant cells' bounds in one flat table (OpenVDB grids only).
  const CellBounds& cell_bounds() const { return cell_bounds_; }
  // Per layer (OpenVDB grids only): its density as a function of depth, for
  // exact flights, where it varies in depth only and its S does not vary.
  const std::vector<std::optional<DepthProfile>>& depth_profiles() const { return depth_profiles_; }

 private:
  SlabGeometry geometry_;
  std::vector<MediumLayer> layers_;
  std::unique_ptr<DensityGrids> grids_;
  std::vector<LayerMajorants> majorants_;
  std::unique_ptr<VoxelDensity> voxels_;
  CellBounds cell_bounds_;
  std::vector<std::optional<DepthProfile>> depth_profiles_;
};

}  // namespace mcref::volume
