// validate/micrograin/geometry_memo: the memoised G_dist diffuse geometry is the
// model's value, bit for bit, whether computed or found, from any thread.
#include <gtest/gtest.h>

#include <vector>

#include <tbb/parallel_for.h>

#include "models/micrograin/micrograin_bsdf.h"
#include "validate/micrograin/geometry_memo.h"

using namespace mcref;
namespace mg = mcref::micrograin;

TEST(GeometryMemo, EqualsTheModelBitForBit) {
  const mg::GrainField f{0.4, 1.0, 1.0};
  std::vector<Vec3> dirs;
  for (double t : {0.1, 0.7, 1.2, 1.5})
    for (double p : {0.0, 1.0, 3.0}) dirs.push_back(spherical_direction(t, p));
  const Vec3 i = spherical_direction(0.6, 0.2);
  for (mg::TwoWay masking : {mg::TwoWay::Product, mg::TwoWay::Union})
    for (double ior : {0.0, 1.5}) {
      std::vector<double> direct(dirs.size()), first(dirs.size()), again(dirs.size());
      for (std::size_t k = 0; k < dirs.size(); ++k) direct[k] = mg::gdist_diffuse_geometry(f, i, dirs[k], ior, masking);
      // Concurrent first calls (several threads may compute one key), then cached ones.
      tbb::parallel_for(std::size_t{0}, dirs.size(), [&](std::size_t k) { first[k] = memo_diffuse_geometry(f, i, dirs[k], ior, masking); });
      for (std::size_t k = 0; k < dirs.size(); ++k) again[k] = memo_diffuse_geometry(f, i, dirs[k], ior, masking);
      for (std::size_t k = 0; k < dirs.size(); ++k) {
        EXPECT_EQ(first[k], direct[k]) << k;
        EXPECT_EQ(again[k], direct[k]) << k;
      }
    }
  // Another field, same directions: not confused with the first.
  const mg::GrainField g{0.9, 0.5, 0.5};
  EXPECT_EQ(memo_diffuse_geometry(g, i, dirs[0], 0.0, mg::TwoWay::Union),
            mg::gdist_diffuse_geometry(g, i, dirs[0], 0.0, mg::TwoWay::Union));
  EXPECT_NE(memo_diffuse_geometry(g, i, dirs[0], 0.0, mg::TwoWay::Union),
            memo_diffuse_geometry(f, i, dirs[0], 0.0, mg::TwoWay::Union));
}
