#pragma once
// The majorant cells' bounds of every layer of an OpenVDB slab
// (sim/slab/majorant_grid.h) in one flat table, for the data-parallel walk's
// lookups (sim/slab/wave_grid_flights.cpp), built once per medium:
//  - lo and hi per cell, in float rounded outward (so still bounds of the
//    density: lo <= rho(x) <= hi in the cell), layer k's cells from offset[k],
//    in majorant_grid.h's order;
//  - per layer and voxel interval in depth (0 at the layer's top), the depth
//    cell holding it, layer k's from depth_offset[k];
//  - per layer, the largest hi: a majorant of the whole layer.
// Floats and ints, not doubles: GCC's vectoriser then knows that a gather from
// these tables does not read the walk's lanes.
#include <cstddef>
#include <vector>

#include "sim/slab/majorant_grid.h"

namespace mcref::volume {

struct CellBounds {
  std::vector<float> lo, hi;
  std::vector<int> depth_cell;
  std::vector<std::size_t> offset, depth_offset;
  std::vector<double> rho_max;
};

// depth_voxels: voxel intervals per layer in depth (the majorants' depth cells
// are runs of them).
CellBounds flatten_cell_bounds(const std::vector<LayerMajorants>& majorants, int depth_voxels);

}  // namespace mcref::volume
