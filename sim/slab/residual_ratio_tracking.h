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
// roulette: the same expectation, and a bounded number of lookups on deep rays).
#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/majorant_grid.h"
#include "sim/slab/voxel_density.h"

namespace mcref::volume {

inline constexpr double kRouletteBelow = 0.1;

// The column of the control density (each depth row's row_lo) between depths a and b.
double control_column(const LayerMajorants& M, double a, double b);

// `estimate` times an estimate of the residual transmittance of `layer` along
// d between its depths a and b, on the ray from `origin` (its x, y, depth; its
// own direction is not used): the points at distance s are origin + s d.
// The roulette above applies to the product, `estimate` included.
double track_residual(const LayerMajorants& M, const VoxelDensity& voxels, int layer, const Photon& origin, Vec3 d,
                      double a, double b, double estimate, Rng& rng);

}  // namespace mcref::volume
