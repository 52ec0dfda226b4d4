#include "sim/slab/residual_ratio_tracking.h"

#include <algorithm>
#include <cmath>

namespace mcref::volume {

double control_column(const LayerMajorants& M, double a, double b) {
  const double shallow = std::min(a, b), deep = std::max(a, b);
  double column = 0;
  for (int iz = 0; iz < M.depth_cells(); ++iz) {
    const double top = std::max(shallow, M.faces[iz]), bottom = std::min(deep, M.faces[iz + 1]);
    if (bottom > top) column += M.row_lo[iz] * (bottom - top);
  }
  return column;
}

namespace {

// The roulette of the header: false if the estimate ends as 0.
bool survives(double& estimate, Rng& rng) {
  if (estimate >= kRouletteBelow) return true;
  if (!(rng.uniform() * kRouletteBelow < estimate)) return false;
  estimate = kRouletteBelow;
  return true;
}

}  // namespace

double track_residual(const LayerMajorants& M, const VoxelDensity& voxels, int layer, const Photon& origin, Vec3 d,
                      double a, double b, double estimate, Rng& rng) {
  if (!survives(estimate, rng)) return 0;
  const bool up = d.z > 0;
  const double f = M.factor(d), shallow = std::min(a, b), deep = std::max(a, b), inv_dz = 1 / d.z;
  const int cells = M.depth_cells();
  long points = 0;
  // The depth rows in the ray's order: bottom to top going up, top to bottom going down.
  for (int n = 0; n < cells; ++n) {
    const int iz = up ? cells - 1 - n : n;
    const double top = std::max(shallow, M.faces[iz]), bottom = std::min(deep, M.faces[iz + 1]);
    const double lo = M.row_lo[iz], range = M.row_hi[iz] - lo, rate = range * f;
    if (!(bottom > top) || !(rate > 0)) continue;
    // depth(s) = origin.depth - d.z s: the ray's distances at the part's entry and exit.
    const double s_out = (origin.depth - (up ? top : bottom)) * inv_dz;
    for (double s = (origin.depth - (up ? bottom : top)) * inv_dz;;) {
      s += -std::log1p(-rng.uniform()) / rate;
      if (s >= s_out) break;
      if (++points > kMaxPoints) return estimate;  // (header)
      const double rho = voxels.density(layer, origin.x + d.x * s, origin.y + d.y * s, origin.depth - d.z * s);
      estimate *= 1 - (rho - lo) / range;
      if (!survives(estimate, rng)) return 0;
    }
  }
  return estimate;
}

}  // namespace mcref::volume
