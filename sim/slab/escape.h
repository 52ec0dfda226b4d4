#pragma once
// The probability that a photon leaves the stack along d without another
// collision: exp(-optical depth) from its point (layer, depth) to the top face
// (d.z > 0) or the bottom face (d.z < 0), summed over the layers crossed:
// sigma_t = rho sigma(d) (SpongeCake Eq. 3) times the path length in a
// homogeneous layer, and sigma(d) / |d.z| times the column of rho
// (sim/slab/depth_profile.h) in an OpenVDB layer varying in depth only.
// 0 toward a substrate (nothing leaves through the bottom) and along the horizon.
// The next-event estimators of sim/slab/walk.h tally it at every event.
#include <string>

#include "sim/slab/medium.h"

namespace mcref::volume {

double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d);

// Why escape_probability cannot serve this medium ("" if it can): an OpenVDB
// layer without a depth profile (its density varies laterally, or its S varies),
// where the optical depth along a ray is not a column.
std::string escape_unsupported(const SlabMedium& medium);

}  // namespace mcref::volume
