#pragma once
// A slab's grids as export-vdb writes them, in types Debian's python3-openvdb
// (pyopenvdb: BoolGrid, FloatGrid, Vec3SGrid) and Blender read:
//   "layer<k>_density"    openvdb::FloatGrid, fog volume
//   "layer<k>_S_diag"     openvdb::Vec3SGrid (S_xx, S_yy, S_zz), SGGX layers only
//   "layer<k>_S_offdiag"  openvdb::Vec3SGrid (S_xy, S_xz, S_yz)
// on voxels (i, j, k), i, j in [0, lateral_voxels), k in [0, depth_voxels], with
// the transform and metadata of the simulation's grids (density_grid.h). The
// periodic seam is stored once: the simulation's column i = N (j = N), a copy
// of i = 0 (j = 0), is left out; a reader wraps i and j modulo N.
// S is rounded to float32 (the simulation keeps it in double): 2^-24 relative
// per component, so S's small eigenvalue alpha^2 of a tilted layer moves by up
// to about 4e-8 / alpha^2 relative (4 % at alpha = 1e-3), and at alpha = 1e-4
// (the smallest allowed) the stored S need not be positive definite.
#include <string>

#include <openvdb/openvdb.h>

#include "sim/slab/density_grid.h"

namespace mcref::volume {

openvdb::GridPtrVec export_grids(const DensityGrids& grids);
// Writes export_grids to a .vdb file (temporary file, then rename).
void write_vdb(const std::string& path, const DensityGrids& grids);

}  // namespace mcref::volume
