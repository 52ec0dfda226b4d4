// Order-1 slab tables against the SpongeCake single-scattering model
// (Eq. 8-16, Sec. 4.4), one and two layers, reflection and transmission;
// a Lambertian substrate seen through a layer (Sec. 4.5); RGB channels.
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

const char* kHead = R"(
[run]
seed = 11
batches = 8
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 65]
theta_o_bins = 8
phi_bins = 8
max_order = 1
samples = 40000
)";

void check_ss(const std::string& geometry) {
  const Experiment ex = parse_experiment(geometry + kHead, "test.toml");
  const std::vector<Table> t = slab_test::run(ex);
  slab_test::expect_exact(t, "brdf_order1_volume", "spongecake_ss_brdf", ex);
  slab_test::expect_exact(t, "brdf_btdf_order1_volume", "spongecake_ss_btdf", ex);
}

}  // namespace

TEST(SlabSingleScattering, SurfaceLayer) {
  check_ss(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.4
optical_thickness = 1.5
albedo = 0.7
f0 = 0.5
)");
}

TEST(SlabSingleScattering, TwoLayersSurfaceOverTiltedFibres) {
  check_ss(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.3
thickness = 0.5
density = 1.0
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.5
orientation_deg = [60, 20]
thickness = 2.0
density = 0.7
)");
}

TEST(SlabSingleScattering, LambertianSubstrateThroughLayer) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
substrate = "lambertian"
substrate_albedo = 0.5
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.6
optical_thickness = 0.8
albedo = 0.9
)" + std::string(kHead), "test.toml");
  const std::vector<Table> t = slab_test::run(ex);
  slab_test::expect_exact(t, "brdf", "spongecake_ss_substrate", ex);
  for (const Table& x : t) EXPECT_EQ(x.name.find("_btdf"), std::string::npos) << "no transmission over a substrate";
}

// f0 = 1: order-1 weights are gamma_c times the same geometric factor, so the
// channels are exactly proportional to the albedos.
TEST(SlabSingleScattering, RgbChannelsScaleWithAlbedo) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
optical_thickness = 1.0
albedo = [0.9, 0.5, 0.2]
)" + std::string(kHead), "test.toml");
  const std::vector<Table> tables = slab_test::run(ex);
  const Table& t = slab_test::find(tables, "brdf_order1_volume");
  const std::vector<double> v = t.values();
  for (std::size_t k = 0; k + 2 < v.size(); k += 3) {
    EXPECT_NEAR(v[k + 1], v[k] * 0.5 / 0.9, 1e-12 * (1 + v[k]));
    EXPECT_NEAR(v[k + 2], v[k] * 0.2 / 0.9, 1e-12 * (1 + v[k]));
  }
}

// A Lambert-sphere layer (no SpongeCake layer type) over SGGX flakes: the
// flakes keep their own sigma(w) and reduced phase F D / 4 (this stack took
// sigma = 1 and albedo times the normalised phase: BTDF model 0.205 against
// the simulation's 0.481).
TEST(SlabSingleScattering, LambertSpheresOverSurfaceFlakes) {
  check_ss(R"([geometry]
kind = "slab"
[[geometry.layer]]
phase = "lambert_sphere"
optical_thickness = 0.3
albedo = 0.9
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.3
optical_thickness = 1.0
albedo = 0.9
f0 = 0.6
)");
}
