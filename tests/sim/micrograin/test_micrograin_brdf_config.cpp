// [material] of micrograin transport: parsing, defaults, presets, and errors
// that name the key and the allowed range (issue #3).
#include <gtest/gtest.h>

#include <string>

#include "models/microfacet/fresnel.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"

using namespace mcref;

namespace {

const std::string kHead = "[geometry]\nkind = \"micrograin\"\ntau0 = 0.5\nbeta = 1.0\n";
const std::string kMeasure = "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0]\nsamples = 10\n";

Experiment parse(const std::string& material) { return parse_experiment(kHead + material + kMeasure, "mat.toml"); }

// Expects a ConfigError whose message contains every fragment.
void expect_error(const std::string& material, std::initializer_list<std::string> fragments) {
  try {
    parse(material);
    ADD_FAILURE() << "no error for:\n" << material;
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    for (const std::string& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
  }
}

}  // namespace

TEST(MicrograinBrdfConfig, ParsesEveryType) {
  const Experiment e = parse(
      "[material.grain]\ntype = \"diffuse_specular\"\nalbedo = [0.1, 0.2, 0.3]\nior = 1.4\n"
      "[material.base]\ntype = \"conductor\"\npreset = \"gold\"\n");
  ASSERT_TRUE(e.materials.configured);
  EXPECT_EQ(e.materials.grain.type, MicroBrdf::Type::DiffuseSpecular);
  EXPECT_DOUBLE_EQ(e.materials.grain.albedo.b, 0.3);
  EXPECT_DOUBLE_EQ(e.materials.grain.ior, 1.4);
  EXPECT_EQ(e.materials.base.type, MicroBrdf::Type::Conductor);
  EXPECT_DOUBLE_EQ(e.materials.base.eta.r, micrograin::kGold.eta[0]);
  EXPECT_DOUBLE_EQ(e.materials.base.kappa.b, micrograin::kGold.kappa[2]);
  const Experiment f = parse(
      "[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"rough_conductor\"\neta = 0.2\nkappa = [3, 2, 1]\nalpha = 0.1\n");
  EXPECT_DOUBLE_EQ(f.materials.grain.albedo.g, 0.8);  // default
  EXPECT_DOUBLE_EQ(f.materials.base.eta.b, 0.2);
  EXPECT_DOUBLE_EQ(f.materials.base.kappa.g, 2.0);
  EXPECT_DOUBLE_EQ(f.materials.base.alpha, 0.1);
  EXPECT_NO_THROW(parse("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"conductor\"\npreset = \"copper\"\n"));
}

TEST(MicrograinBrdfConfig, ErrorsNameKeyAndRange) {
  expect_error("[material.grain]\ntype = \"lambertian\"\nalbdo = 0.5\n[material.base]\ntype = \"black\"\n",
               {"mat.toml", "material.grain.albdo"});
  expect_error("[material.grain]\ntype = \"lambertian\"\nalbedo = 1.5\n[material.base]\ntype = \"black\"\n",
               {"material.grain.albedo", "[0, 1]"});
  expect_error("[material.grain]\ntype = \"lambertian\"\nalbedo = [0.1, 0.2]\n[material.base]\ntype = \"black\"\n",
               {"material.grain.albedo", "three"});
  expect_error("[material.grain]\ntype = \"plastic\"\n[material.base]\ntype = \"black\"\n",
               {"material.grain.type", "lambertian"});
  expect_error("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"conductor\"\n", {"material.base.eta"});
  expect_error("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"conductor\"\npreset = \"gold\"\neta = 1.0\n",
               {"material.base.preset"});
  expect_error("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"conductor\"\npreset = \"silver\"\n",
               {"material.base.preset", "gold"});
  expect_error("[material.grain]\ntype = \"diffuse_specular\"\nior = 0.9\n[material.base]\ntype = \"black\"\n",
               {"material.grain.ior", "(1, 4]"});
  expect_error("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"rough_conductor\"\npreset = \"gold\"\nalpha = 0\n",
               {"material.base.alpha", "(0, 4]"});
  expect_error("[material.grain]\ntype = \"black\"\n", {"material.base"});
  expect_error("[material.grain]\ntype = \"black\"\n[material.base]\ntype = \"black\"\n[material.extra]\n",
               {"material.extra"});
}

TEST(MicrograinBrdfConfig, BrdfNeedsMaterials) {
  // Parsing succeeds; the brdf estimator refuses to run without [material].
  const Experiment e = parse_experiment(kHead + kMeasure, "mat.toml");
  EXPECT_FALSE(e.materials.configured);
}

// [material] without a brdf measure would be ignored (tau+, G1, ... do not
// read it): refused, so that no one believes it shaped those tables.
TEST(MicrograinBrdfConfig, MaterialsWithoutBrdfMeasureAreRefused) {
  const std::string material = "[material.grain]\ntype = \"lambertian\"\n[material.base]\ntype = \"lambertian\"\n";
  try {
    parse_experiment(kHead + material + "[[measure]]\nquantity = \"tau_plus\"\ntheta_i_deg = [0]\nsamples = 10\n", "mat.toml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'material'"), std::string::npos) << what;
    EXPECT_NE(what.find("brdf measures only"), std::string::npos) << what;
  }
  EXPECT_TRUE(parse(material).materials.configured);
}
