#pragma once
// A dense copy of each layer's density voxels (sim/slab/density_grid.h) for
// the lookups of delta tracking (sim/slab/free_flight.cpp): a flat array and
// the trilinear reconstruction of openvdb::tools::BoxSampler, operation for
// operation, so density() returns the bits GridLookup::density() returns
// (same index transform, same corners, same float arithmetic), without the
// value accessor's tree walk. Copied as the grids are when built; it holds
// every value the sampler can read: index planes 0 ... N + 1 laterally and
// 0 ... depth_voxels + 1 in depth (the last ones are reached only with
// weight 0 and read the grid's background, as the sampler does).
#include <cstddef>
#include <vector>

#include "sim/slab/density_grid.h"

namespace mcref::volume {

class VoxelDensity {
 public:
  explicit VoxelDensity(const DensityGrids& grids);
  double density(int layer, double x, double y, double depth) const {
    return sample(layer, grids_.index(layer, x, y, depth));
  }

 private:
  double sample(int layer, const openvdb::Vec3R& ijk) const;
  const DensityGrids& grids_;
  int nx_ = 0, nz_ = 0;  // stored planes per lateral axis, in depth
  std::vector<std::vector<float>> values_;  // per layer, index (i * nx + j) * nz + k
};

inline double VoxelDensity::sample(int layer, const openvdb::Vec3R& ijk) const {
  const openvdb::Vec3i c = openvdb::tools::local_util::floorVec3(ijk);
  const openvdb::Vec3R uvw = ijk - c;
  const float* v = values_[static_cast<std::size_t>(layer)].data() +
                   (static_cast<std::ptrdiff_t>(c[0]) * nx_ + c[1]) * nz_ + c[2];
  const std::ptrdiff_t di = static_cast<std::ptrdiff_t>(nx_) * nz_, dj = nz_;
  // BoxSampler::trilinearInterpolation: a + float((b - a) w) in float.
  const auto lerp = [](float a, float b, double w) { return static_cast<float>(a + static_cast<float>((b - a) * w)); };
  return lerp(lerp(lerp(v[0], v[1], uvw[2]), lerp(v[dj], v[dj + 1], uvw[2]), uvw[1]),
              lerp(lerp(v[di], v[di + 1], uvw[2]), lerp(v[di + dj], v[di + dj + 1], uvw[2]), uvw[1]), uvw[0]);
}

}  // namespace mcref::volume
