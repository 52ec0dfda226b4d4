#pragma once
// The transmittance through a laterally varying OpenVDB layer along a ray,
// estimated without bias, for the next-event estimators (sim/slab/escape.h):
// residual ratio tracking (Novak, Selle & Jarosz 2014, "Residual ratio
// tracking for estimating attenuation in participating media").
//
// In each depth row of majorant cells (sim/slab/majorant_grid.h) the
// extinction sigma_t(x, w) = rho(x) sigma(w) splits into a control
// lo sigma(w) (lo: the row's least density, row_lo) and a residual
// (rho(x) - lo) sigma(w) <= (hi - lo) sigma(w) (hi: the row's largest, row_hi).
// The control's optical depth is sigma(w) / |w_z| times a column
// (control_column), in closed form. The residual's transmittance is estimated
// by ratio tracking: tentative points at rate (hi - lo) sigma(w) along the
// ray, each multiplying the estimate by 1 - (rho(x) - lo) / (hi - lo), in
// [0, 1]; E[product] = exp(-integral of the residual).
// An estimate that falls below kRouletteBelow goes on with probability
// estimate / kRouletteBelow, as kRouletteBelow, or ends as 0 (Russian
// roulette: the same expectation, and fewer lookups on rays whose estimate is
// already small; 0.3 was the best or near it in precision per CPU second among
// 0.01-1, tests/bench/README.md). It does not bound the lookups of a ray through
// voxels near the row's least density, whose factors stay near 1: a ray almost
// parallel to the faces along an empty stripe of the tile would look up without
// end. After kMaxPoints tentative points the estimate so far is returned, as if
// the rest of the ray were as clear as the part tracked (biased there only;
// no such ray reaches it but along such a stripe).
// The bounds are per row of the whole tile: one empty voxel in a row leaves no
// control part there (the rate is then the row's largest density).
#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/majorant_grid.h"
#include "sim/slab/voxel_density.h"

namespace mcref::volume {

inline constexpr double kRouletteBelow = 0.3;
inline constexpr long kMaxPoints = 1L << 20;

// The column of the control density (each depth row's row_lo) between depths a and b.
double control_column(const LayerMajorants& M, double a, double b);

// `estimate` times an estimate of the residual transmittance of `layer` along
// d between its depths a and b, on the ray from `origin` (its x, y, depth; its
// own direction is not used): the points at distance s are origin + s d.
// The roulette above applies to the product, `estimate` included.
double track_residual(const LayerMajorants& M, const VoxelDensity& voxels, int layer, const Photon& origin, Vec3 d,
                      double a, double b, double estimate, Rng& rng);

}  // namespace mcref::volume
