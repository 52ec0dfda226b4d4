// sim/tally/polar_bins: the bin of theta from cos(theta) without acos is
// exactly Axis::find_bin(spherical_theta(...)), for uniform and uneven axes,
// at random z and at every double within 64 ulps of each edge's cosine.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/tally/polar_bins.h"
#include "sim/tally/table.h"

using namespace mcref;

namespace {

int reference_bin(const Axis& a, double z) { return a.find_bin(spherical_theta({0, 0, z})); }

// Counts z where PolarBins and the reference disagree (printing the first few).
int mismatches(const Axis& a, const PolarBins& p, const std::vector<double>& zs) {
  int bad = 0;
  for (double z : zs)
    if (p.bin(z) != reference_bin(a, z) && ++bad <= 5)
      ADD_FAILURE() << a.name << ": z = " << z << " bin " << p.bin(z) << " vs " << reference_bin(a, z);
  return bad;
}

}  // namespace

// 10^6 uniform z in [-1, 1] (seed 7), the doubles within 64 ulps of cos(e)
// for every edge e, and the special values.
TEST(PolarBins, SameBinAsAcos) {
  const std::vector<Axis> axes{
      Axis::uniform_bins("theta 45", "rad", 0.0, kPi / 2, 45),
      Axis::uniform_bins("theta 30", "rad", 0.0, kPi / 2, 30),
      Axis::uniform_bins("theta 1", "rad", 0.0, kPi / 2, 1),
      Axis::uniform_bins("theta 1000", "rad", 0.0, kPi / 2, 1000),
      Axis::uniform_bins("theta full 7", "rad", 0.0, kPi, 7),
      Axis::bins("uneven", "rad", {0.1, 0.5, 0.50001, 1.2, 3.0}),
  };
  Rng rng(7);
  std::vector<double> random_z(1000000);
  for (double& z : random_z) z = 2 * rng.uniform() - 1;
  for (const Axis& a : axes) {
    const PolarBins p(a);
    std::vector<double> zs = random_z;
    for (double e : a.values) {
      double lo = std::cos(e), hi = lo;
      for (int k = 0; k < 64; ++k) {
        lo = std::nextafter(lo, -2.0);
        hi = std::nextafter(hi, 2.0);
        zs.push_back(lo);
        zs.push_back(hi);
      }
      zs.push_back(std::cos(e));
    }
    for (double z : {-1.0, -0.0, 0.0, 1.0, 1e-300, -1e-300, 1.5, -1.5, std::numeric_limits<double>::quiet_NaN()})
      zs.push_back(z);
    EXPECT_EQ(mismatches(a, p, zs), 0) << a.name;
  }
}
