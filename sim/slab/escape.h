#pragma once
// The probability that a photon leaves the stack along d without another
// collision: exp(-optical depth) from its point (layer, depth) to the top face
// (d.z > 0) or the bottom face (d.z < 0), sigma_t = rho sigma(d) per homogeneous
// layer (SpongeCake Eq. 3), summed over the layers crossed. 0 toward a
// substrate (nothing leaves through the bottom) and along the horizon.
// The next-event estimator of sim/slab/walk.h tallies it at every event.
#include "sim/slab/medium.h"

namespace mcref::volume {

double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d);

}  // namespace mcref::volume
