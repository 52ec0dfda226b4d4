#pragma once
// One realization of a micrograin field (sim/micrograin/micrograin_field.h) as an
// OpenVDB occupancy grid, for mcref export-vdb and tests.
//
// Grid "grains" (openvdb::FloatGrid, class fog volume): 1 where the voxel
// centre lies inside a grain (the upper half-ellipsoids z >= 0), 0 outside
// (background, not stored). Voxels cover the periodic tile [0, L)^2 and
// z in [0, c] (c the vertical semi-axis): nx = max(1, round(L / h)) voxels per
// side of lateral size L / nx, nz = max(1, ceil(c / h)) layers of height c / nz,
// for a requested voxel size h (default radius / 8). Cell-centred: voxel
// (i, j, k) has its centre at ((i + 1/2) L / nx, (j + 1/2) L / nx, (k + 1/2) c / nz),
// which is what the grid's transform maps index (i, j, k) to.
// Metadata: tau0, beta_x, beta_y, radius, tile (in radii), tile_side (real
// units), c, seed, grain_count.
#include <cstdint>
#include <string>

#include <openvdb/openvdb.h>

#include "sim/micrograin/micrograin_field.h"

namespace mcref {


struct MicrograinVoxels {
  int nx = 1, nz = 1;        // voxels per tile side, voxel layers in z
  double hx = 1, hz = 1;     // voxel sizes (real units)
  double count() const { return static_cast<double>(nx) * nx * nz; }
};
// The voxel layout for a requested voxel size (<= 0: radius / 8).
MicrograinVoxels micrograin_voxels(const MicrograinGeometry& g, double voxel_size);
// The voxel count for messages ("1.2e+09").
std::string voxel_count_text(const MicrograinVoxels& v);
// Largest voxel count export-vdb accepts.
inline constexpr double kMaxMicrograinVoxels = 2e8;

// Voxelises the field (throws std::invalid_argument above kMaxMicrograinVoxels),
// realization `realization` of run.seed `run_seed`: both are metadata (seed,
// realization), so that the field can be built again from them
// (micrograin_realization_seed).
openvdb::FloatGrid::Ptr micrograin_grid(const MicrograinField& field, const MicrograinVoxels& v, std::uint64_t run_seed,
                                        std::uint64_t realization);
void write_micrograin_vdb(const std::string& path, const openvdb::FloatGrid::Ptr& grid);

}  // namespace mcref
