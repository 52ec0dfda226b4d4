#pragma once
// Free flights through the layer stack. Both backends share one tracking
// loop over the layers crossed along the ray:
//  - homogeneous: exact exponential sampling with sigma_t(w) = rho sigma(w),
//    the optical depth carried across layer faces (exact for piecewise-constant media);
//  - OpenVDB: delta tracking (exact for any density field; Woodcock 1965).
//    Non-SGGX layers: against rho_max (sigma = 1), accepted with probability
//    rho(x) / rho_max. SGGX layers: sigma_t(x, w) = rho(x) sigma(w; S(x)) with
//    S(x) read from the layer's S grids, against the direction-free majorant
//    rho_max * max sqrt(lambda_max(S)); accepted with probability
//    sigma_t(x, w) / majorant, and the scattering event then uses S(x) (D, sigma
//    and the visible-normal sampler of that point).
#include <memory>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/slab/medium.h"

namespace mcref::volume {

struct Photon {
  double x = 0, y = 0, depth = 0;  // lateral position and depth below the top face
  Vec3 d{0, 0, -1};                // propagation direction (d.z < 0: going deeper)
  int layer = 0;                   // index of the layer the photon is in
  void advance(double s) {
    x += d.x * s;
    y += d.y * s;
    depth -= d.z * s;
  }
};

enum class Flight { kCollision, kExitTop, kExitBottom, kLost };

class FreeFlight {
 public:
  virtual ~FreeFlight() = default;
  // Moves the photon to its next real collision (layer set), or to the top
  // face (kExitTop) or the bottom face (kExitBottom, layer = last).
  virtual Flight fly(Photon& p, Rng& rng) = 0;
  // The scattering event at the collision fly() just returned (the photon in
  // `layer`); wi = -propagation direction. Default: the layer's phase function.
  virtual ScatterSample scatter(const MediumLayer& layer, int layer_index, Vec3 wi, Rng& rng) {
    return layer.phase->sample(wi, rng);
  }
  // Lateral period of the medium (0: laterally uniform, position irrelevant).
  virtual double lateral_period() const { return 0; }
};

// One per thread/chunk (grid flights own OpenVDB accessors).
std::unique_ptr<FreeFlight> make_flight(const SlabMedium& medium);
std::unique_ptr<FreeFlight> make_homogeneous_flight(const SlabMedium& medium);

}  // namespace mcref::volume
