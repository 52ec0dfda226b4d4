#pragma once
// Free flights through the layer stack, layer by layer along the ray:
//  - homogeneous: exact exponential sampling with sigma_t(w) = rho sigma(w),
//    the optical depth carried across layer faces (exact for piecewise-constant media);
//  - OpenVDB: delta tracking (exact for any density field; Woodcock 1965)
//    against per-cell majorants hi(cell) factor(w) walked with a 3-D DDA
//    (sim/slab/majorant_grid.h). A tentative collision at x is real with
//    probability sigma_t(x, w) / majorant, sigma_t(x, w) = rho(x) sigma(w; S(x))
//    (sigma = 1 for non-SGGX layers); the scattering event then uses the S of
//    that point (the layer's one S, or S(x) read from the grids where it varies).
//    A layer varying in depth only, with one S, is flown exactly instead, by
//    inverting its optical depth (sim/slab/depth_profile.h).
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
