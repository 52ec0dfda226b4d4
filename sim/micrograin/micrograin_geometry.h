#pragma once
// The parameters of a micrograin field (LRPB23 Sec. 3), as the experiment's
// [geometry] table gives them: filling factor, slope scales, radius and tile.
#include <cstdint>

#include "models/core/rng.h"

namespace mcref {

// Random stream of a realization's grain centres: stream_seed({run seed,
// realization, kGeometryStream}) (measures use their own index instead).
inline constexpr std::uint64_t kGeometryStream = 0xFFFFFFFFull;
// The seed of realization `realization` of a run (simulate and export-vdb).
inline std::uint64_t micrograin_realization_seed(std::uint64_t run_seed, std::uint64_t realization) {
  return stream_seed({run_seed, realization, kGeometryStream});
}

struct MicrograinGeometry {
  double tau0 = 0.5;     // filling factor (LRPB23 Eq. 13), in (0, 1)
  double beta_x = 1.0;   // slope scale c / r_x
  double beta_y = 1.0;   // slope scale c / r_y
  double radius = 1.0;   // sqrt(r_x r_y), the (geometric-mean) horizontal radius
  double tile = 100.0;   // tile side, in units of `radius`
  bool anisotropic() const { return beta_x != beta_y; }
  // Semi-axes: c = radius sqrt(beta_x beta_y), r_x = c / beta_x, r_y = c / beta_y.
  double c() const;
  double r_x() const;
  double r_y() const;
  // Centre density per unit real area: rho = -ln(1 - tau0) / (pi r_x r_y).
  double density() const;
  // Density in unit space: -ln(1 - tau0) / pi.
  double unit_density() const;
};

}  // namespace mcref
