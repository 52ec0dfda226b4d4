#pragma once
// Per-cell majorants of the extinction of an OpenVDB slab, for delta tracking
// (Woodcock 1965) with a 3-D DDA over coarse cells (Amanatides & Woo 1987) in
// sim/slab/free_flight.cpp.
//
// Extinction: sigma_t(x, w) = rho(x) sigma(w; S(x)), sigma(w; S) = sqrt(w^T S w)
// (SpongeCake Eq. 3; sigma = 1 for non-SGGX layers). The flights reconstruct
// rho (VoxelDensity) and S (GridLookup, BoxSampler) trilinearly from the voxels
// at the corners of the voxel cell around x: a convex combination of them
// (to rounding, which kMargin covers), so in a voxel cell
//   min_corners rho <= rho(x) <= max_corners rho (over a sub-box of the voxel
//   cell: min and max over the sub-box's corners, rho being multilinear),
//   sigma(w; S(x))^2 = sum_i w_i w^T S_i w <= max_corners lambda_max(S_i).
// The column past the last one is read as stored (column N) and, on the tile's
// edge, where a lookup wraps to x = 0, as column 0: the bounds hold whether or
// not the grid stores the periodic seam.
//
// Cells: laterally kSubdivision^2 per voxel column (m = kSubdivision
// lateral_voxels; or one per square block of columns, for tests), or one for
// the whole tile when the layer's density does not vary laterally (m = 1). In a
// voxel cell the reconstruction is multilinear (trilinear), so over a cell's
// part in one voxel cell its bounds are at that part's corners: the voxels'
// interpolant there (in double) is what lo and hi bound; in depth,
// runs of voxel intervals, merged while in every column the run's bounds stay
// within kMergeRange of each interval's own (a constant profile: one cell). Per cell:
//  - hi: rho_max * sqrt(max lambda_max(S)) if the layer's S varies, else rho_max;
//    the majorant along w is hi * factor(w), factor(w) = sigma(w; S) for an SGGX
//    layer with one S everywhere (exact in direction), else 1;
//  - lo: rho_min for layers whose S does not vary (0 otherwise): a tentative
//    collision with u hi < lo is real whatever rho(x) is (no lookup needed);
//  - ahead_hi (laterally varying layers), per box shape (rx, ry) and quadrant q
//    of the direction (q = [w_x < 0] + 2 [w_y < 0]): the max of hi over the
//    (rx + 1)(ry + 1) lateral cells from the cell rx cells ahead along x and ry
//    along y (wrapped around the tile), in its depth cell: a majorant in that box,
//    which the flights use from the photon's cell, restarting where it leaves the
//    box (free_flight.cpp). Shapes: square (r = reach), and r along the direction's
//    major axis by about r / 4 or r / 2 across it (narrow_reach), for directions
//    whose path over r + 1 cells stays within that band. Computed separably: the
//    max along x, then along y; stored rounded up to the least of 256 levels
//    above it (0, then geometric with a ratio of at most 1.05 up to the layer's
//    largest hi), as its index: a byte per box, so that the 20 tables of a
//    32 x 32-cell layer (20 KiB) stay in the L1 cache, where doubles (160 KiB)
//    did not (tests/bench/README.md).
// hi and lo carry a relative margin of kMargin for the single-precision
// interpolation of the density voxels.
#include <array>
#include <vector>

#include "models/core/vec.h"
#include "models/sggx/sggx_distribution.h"

namespace mcref::volume {

class DensityGrids;

inline constexpr double kMergeRange = 0.1;
inline constexpr double kMargin = 1e-5;
inline constexpr int kSubdivision = 2;  // lateral cells per voxel side (by default)

struct LayerMajorants {
  int lateral = 1;                // m: cells per tile side
  double cell_size = 1;           // tile / m
  double inv_cell_size = 1;       // m / tile
  std::vector<double> faces;      // depths of the cell faces, top to bottom (cells + 1)
  std::vector<double> hi, lo;     // per cell, index (depth_cell * m + j) * m + i
  std::vector<double> row_hi;     // max of hi over each depth row of cells
  std::vector<double> row_lo;     // min of lo over each depth row of cells
  int reach = 0;                  // r: lateral cells ahead of the photon's (lateral > 1)
  std::array<std::array<int, 2>, 5> box_reach{};  // per box shape: cells ahead along x, along y
  int narrow_reach[2] = {0, 0};   // the narrow boxes' reach across the major axis (shapes 2, 4 and 1, 3)
  std::vector<unsigned char> ahead_hi;     // index (shape * 4 + q) * hi.size() + cell: level of the box ahead
  std::array<double, 256> ahead_levels{};  // 0, then geometric up to the layer's max hi
  bool one_s = false;             // SGGX layer with one S everywhere (s)
  bool s_varies = false;          // SGGX layer whose S varies: look S up at collisions
  sggx::Sggx s;
  int depth_cells() const { return static_cast<int>(faces.size()) - 1; }
  double factor(Vec3 w) const { return one_s ? sggx::projected_area(s, w) : 1.0; }
};

// The majorants of every layer of the grids (as they are when built);
// lateral_block voxel columns per cell side (a divisor of lateral_voxels; 0: the
// default, kSubdivision cells per voxel side; 1: one cell per voxel column;
// lateral_voxels: one per layer and depth run);
// reach: r of ahead_hi (clamped to [1, lateral - 1]; 0: the cells in a mean free path
// at the mean of hi and the largest factor(w), rounded).
std::vector<LayerMajorants> build_majorants(const DensityGrids& grids, int lateral_block = 0, int reach = 0);

}  // namespace mcref::volume
