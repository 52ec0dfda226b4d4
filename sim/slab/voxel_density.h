#pragma once
// A dense copy of each layer's density voxels (sim/slab/density_grid.h) for
// the lookups of delta tracking (sim/slab/free_flight.cpp): the trilinear
// reconstruction of openvdb::tools::BoxSampler (the same corners and weights)
// over a flat array, in double where BoxSampler rounds each interpolation to
// float, with the index-space transform done by multiplications and an
// integer floor instead of divisions and fmod, and without the value
// accessor's tree walk. Both are convex combinations of the corner voxels
// (to rounding), which is what the majorants bound (sim/slab/majorant_grid.h);
// they differ by the sampler's float rounding. Copied as the grids are when
// built: index planes 0 ... N laterally (the stored seam N included) and
// 0 ... depth_voxels + 1 in depth (the last one, the grid's background, is
// read with weight 0 on the bottom face, as the sampler reads it).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "sim/slab/density_grid.h"
#include "sim/slab/depth_profile.h"

namespace mcref::volume {

// v wrapped periodically into [0, n) (inv_n = 1 / n): a floor without a libm
// call or a division; q may round across an integer, which the last two
// lines undo.
inline double wrap_periodic(double v, double n, double inv_n) {
  const double q = v * inv_n;
  long fl = static_cast<long>(q);
  fl -= q < static_cast<double>(fl);
  double w = v - n * static_cast<double>(fl);
  w = w < 0 ? w + n : w;
  return w >= n ? w - n : w;
}

class VoxelDensity {
 public:
  explicit VoxelDensity(const DensityGrids& grids);
  // The density at a point of layer k (lateral coordinates anywhere: periodic).
  double density(int k, double x, double y, double depth) const;
  // Layer k's density as a function of depth alone, if every stored column
  // of its voxels holds the same values (the lookups then do not depend on
  // x, y): exactly what density() reconstructs there.
  std::optional<DepthProfile> depth_profile(int k) const;

 private:
  struct Layer {
    double top = 0, bottom = 0, inv_hz = 1;
    std::vector<float> values;  // index (i * planes + j) * depth_planes + k
  };
  std::vector<Layer> layers_;
  double inv_hx_ = 1, n_ = 1, inv_n_ = 1, nz_ = 1;
  std::ptrdiff_t planes_ = 0, depth_planes_ = 0;  // stored per lateral axis (N + 1), in depth
};

inline double VoxelDensity::density(int k, double x, double y, double depth) const {
  const Layer& l = layers_[static_cast<std::size_t>(k)];
  double ix = x * inv_hx_, iy = y * inv_hx_;  // in [0, N) already: wrap_periodic would return them as they are
  if (!(ix >= 0 && ix < n_)) ix = wrap_periodic(ix, n_, inv_n_);
  if (!(iy >= 0 && iy < n_)) iy = wrap_periodic(iy, n_, inv_n_);
  const double iz = std::min(nz_, std::max(0.0, (l.bottom - depth) * l.inv_hz));  // (std::fmin is a libm call)
  const int ci = static_cast<int>(ix), cj = static_cast<int>(iy), ck = static_cast<int>(iz);  // >= 0: floor
  const double u = ix - ci, v = iy - cj, w = iz - ck;
  const float* p = l.values.data() + (ci * planes_ + cj) * depth_planes_ + ck;
  const std::ptrdiff_t di = planes_ * depth_planes_, dj = depth_planes_;
  // Trilinear in double (OpenVDB's BoxSampler rounds each step to float).
  const auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  return lerp(lerp(lerp(p[0], p[1], w), lerp(p[dj], p[dj + 1], w), v),
              lerp(lerp(p[di], p[di + 1], w), lerp(p[di + dj], p[di + dj + 1], w), v), u);
}

}  // namespace mcref::volume
