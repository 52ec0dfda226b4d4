// [geometry] kind = "slab": parsing and every error naming its key and range.
#include <gtest/gtest.h>

#include <string>

#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"

using namespace mcref;

namespace {
const char* kMeasure = "\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [30]\nsamples = 10\n";

std::string error_of(const std::string& geometry) {
  try {
    parse_experiment(geometry + kMeasure, "t.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SlabConfig, ParsesLayersSubstrateAndOptions) {
  const Experiment e = parse_experiment(R"([geometry]
kind = "slab"
substrate = "rough_conductor"
substrate_alpha = 0.2
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.3
orientation_deg = [90, 0]
thickness = 2
optical_thickness = 4
albedo = [0.9, 0.5, 0.1]
f0 = 0.04
[[geometry.layer]]
phase = "hg"
g = -0.3
density = 3
)" + std::string(kMeasure), "t.toml");
  ASSERT_EQ(e.slab.layers.size(), 2u);
  EXPECT_NEAR(e.slab.layers[0].density, 2.0, 1e-12);
  EXPECT_NEAR(e.slab.layers[0].orientation.x, 1.0, 1e-12);
  EXPECT_EQ(e.slab.layers[0].albedo.b, 0.1);
  EXPECT_EQ(e.slab.layers[1].g, -0.3);
  EXPECT_EQ(e.slab.substrate.kind, SlabSubstrate::Kind::kRoughConductor);
  EXPECT_FALSE(e.isotropic);  // horizontal fibres
  EXPECT_EQ(e.measures[0].phi_bins, 36);
}

TEST(SlabConfig, ErrorsNameKeyAndRange) {
  const std::string head = "[geometry]\nkind = \"slab\"\n";
  EXPECT_NE(error_of(head).find("'geometry.layer'"), std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"foam\"\n").find("geometry.layer.0.phase"), std::string::npos);
  const std::string bad_alpha = error_of(head + "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0\n");
  EXPECT_NE(bad_alpha.find("geometry.layer.0.alpha"), std::string::npos) << bad_alpha;
  EXPECT_NE(bad_alpha.find("[0.0001, 1000]"), std::string::npos) << bad_alpha;
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"hg\"\ng = 1\n").find("geometry.layer.0.g"), std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\nalbedo = [0.5, 0.5]\n").find("geometry.layer.0.albedo"),
            std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\nalbedo = 1.5\n").find("[0, 1]"), std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\ndensity = 1\noptical_thickness = 2\n")
                .find("optical_thickness"),
            std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\nalpha = 0.5\n").find("geometry.layer.0.alpha"),
            std::string::npos);  // alpha is not a key of isotropic layers
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\nprofile = \"linear\"\nprofile_top = 1\nprofile_bottom = 2\n")
                .find("geometry.layer.0.profile"),
            std::string::npos);
  EXPECT_NE(error_of(head + "substrate = \"glass\"\n[[geometry.layer]]\nphase = \"isotropic\"\n").find("geometry.substrate"),
            std::string::npos);
  EXPECT_NE(error_of(head + "substrate = \"lambertian\"\nsubstrate_albedo = -1\n[[geometry.layer]]\nphase = \"isotropic\"\n")
                .find("geometry.substrate_albedo"),
            std::string::npos);
  EXPECT_NE(error_of(head + "backend = \"openvdb\"\nprofile = 3\n[[geometry.layer]]\nphase = \"isotropic\"\n").find("geometry.profile"),
            std::string::npos);
  EXPECT_NE(error_of(head + "[[geometry.layer]]\nphase = \"sggx_surface\"\nalpha = 0.5\norientation = [0, 0, 0]\n")
                .find("geometry.layer.0.orientation"),
            std::string::npos);
}

// Keys that cannot take effect are refused, as every inapplicable key is:
// delta_transmission over a substrate; a
// density from optical_thickness / thickness above the density key's 1e9
// (a subnormal thickness made it infinite); and a profile table whose
// breakpoints fall between voxel planes (with 3 voxels, [1, 4, 1] simulated
// an optical thickness of 1.87 instead of 2).
TEST(SlabConfig, KeysThatCannotTakeEffectAreRefused) {
  const std::string head = "[geometry]\nkind = \"slab\"\n";
  const std::string iso = "[[geometry.layer]]\nphase = \"isotropic\"\n";
  const std::string delta = error_of(head + "substrate = \"lambertian\"\ndelta_transmission = false\n" + iso);
  EXPECT_NE(delta.find("geometry.delta_transmission"), std::string::npos) << delta;
  EXPECT_EQ(error_of(head + "delta_transmission = false\n" + iso), "");
  const std::string thin = error_of(head + "[[geometry.layer]]\nphase = \"isotropic\"\nthickness = 1e-320\noptical_thickness = 1\n");
  EXPECT_NE(thin.find("geometry.layer.0.optical_thickness"), std::string::npos) << thin;
  EXPECT_NE(thin.find("more than 1e9"), std::string::npos) << thin;
  const std::string table = "[[geometry.layer]]\nphase = \"isotropic\"\nprofile = \"table\"\nprofile_table = [1, 4, 1, 2]\n";
  const std::string cut = error_of(head + "backend = \"openvdb\"\ndepth_voxels = 32\n" + table);
  for (const char* piece : {"geometry.layer.0.profile_table", "3 intervals", "depth_voxels = 32", "use depth_voxels = 33"})
    EXPECT_NE(cut.find(piece), std::string::npos) << piece << " missing from: " << cut;
  EXPECT_EQ(error_of(head + "backend = \"openvdb\"\ndepth_voxels = 33\n" + table), "");
}
