#pragma once
// The data-parallel walk's free flights through OpenVDB layers (sim/slab/wave_walk.cpp
// runs them; sim/slab/wave_lanes.h holds the lanes): delta tracking against the
// cells' bounds, or exact flights through depth profiles. Each is a vectorised
// stage over the lanes (built for AVX-512, AVX2 and baseline x86-64).
#include "sim/slab/wave_lanes.h"

namespace mcref::volume::wave {

// OpenVDB layers (S the same everywhere in each): delta tracking against the
// layer's majorant rho_max sigma(w; S) (the Stack's density is rho_max, the max
// of the layer's cell majorants hi, sim/slab/majorant_grid.h), exact in
// direction; a tentative collision at x is real with probability
// rho(x) / rho_max, decided by u rho_max against its cell's bounds lo <= rho <= hi
// (real below lo, null from hi) and, in between, from the voxels (kLookup).
// Cells: the majorants' own (lateral m x m per tile, depth runs of voxel
// intervals), read from the medium's flat tables (sim/slab/cell_bounds.h),
// passed beside this.
struct Grid {
  double offset[kMaxLayers], depth_offset[kMaxLayers], m[kMaxLayers], inv_cell[kMaxLayers], inv_hz[kMaxLayers];
  double intervals;          // voxel intervals per layer in depth
  double last;               // the last cell's index
  double tile, inv_tile;     // lateral period
  bool lateral, depth;       // some layer varies laterally; some layer has more than one depth cell
};

// The flights of lanes 0..n-1 (on paths b if in_b, else a): outcome in Steps::event,
// kLookup lanes' acceptance draw in Lateral::v; lo, hi, depth_cell: CellBounds' tables.
void fly_grid(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo, const float* hi,
              const int* depth_cell);

// OpenVDB stacks whose layers all vary in depth only, each with one S (every
// stack a TOML describes): exact flights, as free_flight.cpp's fly_profile
// (sim/slab/depth_profile.h). The column of rho to go is tau |w_z| / sigma(w);
// from the start's column, the interval where the column reaches its target is
// the table's guess or the one after it (else, for thin intervals, the scalar
// pass flies the lane: kDeferred, the column to go in Lateral::v); then one
// quadratic. No null collisions, no voxel lookups. A path that reaches an inner
// face crosses it in the scalar pass and draws a new exponential there (the
// same law: it is memoryless). Layer k's planes (rho, column) and table
// entries start at plane0[k] and entry0[k] of the flat tables passed beside this.
struct Profiles {
  double plane0[kMaxLayers], entry0[kMaxLayers], entries[kMaxLayers];
  double last[kMaxLayers];      // the last interval's index (planes - 2)
  double inv_step[kMaxLayers];  // table entries per unit of column (index units: rho x planes)
  double total[kMaxLayers];     // the layer's whole column
  double hz[kMaxLayers], inv_hz[kMaxLayers];
};

// The flights of lanes 0..n-1 (on paths b if in_b, else a): outcome in Steps::event,
// kDeferred lanes' column still to go in Lateral::v; rho, column, interval_of: the
// layers' DepthProfile tables, flat.
void fly_profiles(Lanes& L, bool in_b, int n, const Stack& l, const Profiles& q, const double* rho,
                  const double* column, const int* interval_of);

}  // namespace mcref::volume::wave
