#pragma once
// A slab's densities read from an OpenVDB file (geometry.density_vdb), laid out
// as export-vdb writes them (sim/slab/slab_vdb.h), so an exported slab can be
// edited (in Houdini, Blender or pyopenvdb) and simulated again:
//   "layer<k>_density"  FloatGrid, one per layer k of the experiment, on voxels
//                       (i, j, k'), i, j in [0, lateral_voxels) (the periodic
//                       tile, its seam not stored), k' in [0, depth_voxels]
//                       (k' = 0 on the layer's bottom face), with the transform
//                       x = i tile / lateral_voxels, y = j tile / lateral_voxels,
//                       z = k' thickness / depth_voxels - (depth of the bottom face);
//                       values rho, finite, in [0, 1e9]; an inactive voxel reads
//                       as the value the grid stores for it (its background where
//                       nothing is stored). Where the grid has export-vdb's metadata
//                       lateral_period and thickness, they must be the experiment's.
//   "layer<k>_S_diag", "layer<k>_S_offdiag"   optional (SGGX layers): S is the
//                       experiment's (alpha, orientation); grids in the file must
//                       hold that S (to their precision, float32 or double), so
//                       that none is silently ignored.
// No other grid is allowed. Everything is checked before any work starts, each
// error naming the file, the grid and the voxel.
#include <string>

#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

// Fills each layer's voxels, density (the layer's mean) and varies_laterally
// from `path` (already resolved; `config_file` and `key` name where it was
// given, for a missing or unreadable file); returns its content's digest
// (sim/hdf5/file_seal.h content_digest).
// Throws ConfigError.
std::string read_density_vdb(const std::string& path, const std::string& config_file, const std::string& key,
                             SlabGeometry& geometry);

}  // namespace mcref::volume
