// White furnace (conservative stacks: R + T_scattered = 1 - T_delta),
// Chandrasekhar's isotropic half-space (all orders), the unscattered
// transmission, and bit-identical tables for 1 and 2 threads.
#include <cmath>

#include "models/sggx/single_scattering.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

TEST(SlabEnergy, WhiteFurnaceTwoLayers) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.3
thickness = 1.0
density = 1.5
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.6
orientation = [0, 1, 0.3]
thickness = 1.0
density = 1.0
[run]
seed = 5
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [0, 30, 60, 85]
phi_i_deg = [0, 45]
theta_o_bins = 4
phi_bins = 4
samples = 20000
)", "test.toml");
  const std::vector<Table> t = slab_test::run(ex);
  slab_test::expect_white_furnace(t, ex, 8);
}

TEST(SlabEnergy, UnscatteredTransmission) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.2
orientation = [1, 0, 0]
optical_thickness = 0.8
albedo = 0.5
[run]
seed = 6
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [0, 50, 75]
phi_i_deg = [0, 90]
theta_o_bins = 2
phi_bins = 2
samples = 20000
)", "test.toml");
  const std::vector<Table> tables = slab_test::run(ex);
  const Table& d = slab_test::find(tables, "brdf_btdf_delta");
  const std::size_t comps = d.axes[2].size();
  std::vector<sggx::Layer> stack{sggx::sggx_layer(1.0, 0.8, sggx::fiber_like(0.2, {1, 0, 0}), 0.5, 1.0)};
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 2; ++b) {
      const Vec3 wi = spherical_direction(d.axes[0].values[a], d.axes[1].values[b]);
      const double expected = sggx::delta_transmittance(stack, wi);
      const std::size_t i = ((a * 2 + b) * comps + comps - 1) * 3;
      EXPECT_NEAR(d.value(i), expected, 4.5 * d.stderr_of(i)) << "theta_i " << a << " phi_i " << b;
      // Order 0 is in the total only: without a substrate no component holds a delta lobe.
      for (std::size_t c = 0; c + 1 < comps; ++c) EXPECT_EQ(d.value(((a * 2 + b) * comps + c) * 3), 0.0) << c;
    }
}

TEST(SlabEnergy, ChandrasekharHalfSpace) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "isotropic"
optical_thickness = 60.0
albedo = 0.9
[run]
seed = 7
batches = 10
[[measure]]
quantity = "brdf"
theta_i_deg = [10, 45, 75]
theta_o_bins = 8
phi_bins = 4
samples = 40000
)", "test.toml");
  slab_test::expect_exact(slab_test::run(ex), "brdf", "chandrasekhar_isotropic", ex);
}

TEST(SlabEnergy, BitIdenticalForOneAndTwoThreads) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
optical_thickness = 2.0
albedo = [0.9, 0.8, 0.7]
[run]
seed = 8
batches = 3
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 20000
)", "test.toml");
  slab_test::expect_bit_identical_threads(ex);
}
