#pragma once
// The probability that a photon leaves the stack along d without another
// collision: exp(-optical depth) from its point (layer, depth) to the top face
// (d.z > 0) or the bottom face (d.z < 0), summed over the layers crossed:
// sigma_t = rho sigma(d) (SpongeCake Eq. 3) times the path length in a
// homogeneous layer, and sigma(d) / |d.z| times the column of rho
// (sim/slab/depth_profile.h) in an OpenVDB layer varying in depth only.
// 0 toward a substrate (nothing leaves through the bottom) and along the horizon.
// Through an OpenVDB layer whose density varies laterally the optical depth is
// not a column: escape_estimate estimates the probability without bias there
// (sim/slab/residual_ratio_tracking.h).
// The next-event estimators of sim/slab/walk.h tally it at every event.
#include <string>

#include "models/core/rng.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"

namespace mcref::volume {

// Exact; throws std::invalid_argument if the ray crosses a laterally varying layer.
double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d);

// From the photon's point (p.layer, p.x, p.y, p.depth) along d: escape_probability
// where every layer crossed varies in depth only (no random numbers drawn), and an
// unbiased estimate of it, in [0, 1], where the ray crosses a laterally varying layer.
double escape_estimate(const SlabMedium& medium, const Photon& p, Vec3 d, Rng& rng);

// Why escape_estimate cannot serve this medium ("" if it can): an OpenVDB
// layer whose SGGX matrix S varies (its extinction is not rho(x) times one sigma(d)).
std::string escape_unsupported(const SlabMedium& medium);

}  // namespace mcref::volume
