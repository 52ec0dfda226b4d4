// The dense copy of the density voxels (sim/slab/voxel_density.h) agrees with
// OpenVDB's trilinear sampler (GridLookup::density, which rounds each of its
// 7 interpolations to float) to 1e-6 of the largest voxel (4.1) at random
// points of every layer, in lateral images of the tile, on voxel planes, within rounding of them, on the tile's edges and on
// the layer's faces; the voxels are random, the stored seam columns repeat
// columns 0 as DensityGrids stores them (with a seam that does not, a point on
// the tile's edge reads either column: test_slab_majorants checks that the
// majorants bound both).
#include <gtest/gtest.h>

#include <cmath>

#include "models/core/rng.h"
#include "sim/experiment/experiment.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/voxel_density.h"

using namespace mcref;

TEST(SlabVoxelDensity, AgreesWithTheOpenVdbSampler) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
tile = 2.0
lateral_voxels = 5
depth_voxels = 6
[[geometry.layer]]
phase = "isotropic"
thickness = 0.5
density = 3.0
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.2
thickness = 1.3
density = 1.5
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)", "v.toml");
  const SlabGeometry& g = ex.slab;
  Rng rng(11);
  volume::DensityGrids grids(g);
  const int n = g.grid.lateral_voxels, nz = g.grid.depth_voxels;
  for (const openvdb::FloatGrid::Ptr& grid : grids.grids()) {
    auto acc = grid->getAccessor();
    for (int z = 0; z <= nz; ++z)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
          acc.setValue(openvdb::Coord(i, j, z), i == n || j == n ? acc.getValue(openvdb::Coord(i % n, j % n, z))
                                                                 : static_cast<float>(0.1 + 4 * rng.uniform()));
  }
  const volume::VoxelDensity dense(grids);
  volume::GridLookup lookup(grids);
  const double tile = g.grid.tile, h = tile / n;
  std::size_t samples = 0, differ = 0;
  double top = 0;
  for (int k = 0; k < 2; ++k) {
    const double thickness = g.layers[k].thickness, hz = thickness / nz;
    // A coordinate on a voxel plane, within rounding of one, or anywhere.
    const auto coordinate = [&](double step, int planes, double lo) {
      const double u = rng.uniform(), plane = lo + step * std::floor(rng.uniform() * (planes + 1));
      if (u < 0.2) return plane;
      if (u < 0.3) return std::nextafter(plane, -INFINITY);
      if (u < 0.4) return std::nextafter(plane, INFINITY);
      return lo + step * planes * rng.uniform();
    };
    for (int s = 0; s < 200000; ++s, ++samples) {
      const double x = coordinate(h, n, 0) + tile * std::floor(7 * rng.uniform() - 3);
      const double y = coordinate(h, n, 0) + tile * std::floor(7 * rng.uniform() - 3);
      const double depth = std::fmin(top + thickness, std::fmax(top, coordinate(hz, nz, top)));
      const double a = dense.density(k, x, y, depth), b = lookup.density(k, x, y, depth);
      if (!(std::fabs(a - b) <= 1e-6 * 4.1) && ++differ == 1)
        ADD_FAILURE() << "layer " << k << " at (" << x << ", " << y << ", " << depth << "): dense " << a << ", sampler " << b;
    }
    top += thickness;
  }
  EXPECT_EQ(samples, 400000u);
  EXPECT_EQ(differ, 0u);
}
