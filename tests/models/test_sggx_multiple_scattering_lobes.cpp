// SpongeCake's multiple-scattering lobes (Sec. 5): with W1 = 1, W2 = 0 and
// unmodified parameters they are the single-scattering model; modified
// parameters keep each layer's flake type and orientation; the Lambertian lobe
// carries its stated energy per side (quadrature); the form is reciprocal and
// linear in (W1, W2); bad input names the key.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/sggx/multiple_scattering_lobes.h"
#include "models/sggx/single_scattering.h"

namespace {

using mcref::Rgb;
using mcref::Vec3;
using mcref::kPi;
namespace sg = mcref::sggx;

// Uniform direction on the sphere (either side), away from grazing.
Vec3 random_direction(mcref::Rng& rng) {
  const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform();
  const double s = std::sqrt(1 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

sg::FlakeLayer random_layer(mcref::Rng& rng, sg::FlakeType type) {
  sg::FlakeLayer l;
  l.type = type;
  l.alpha = 0.05 + 0.95 * rng.uniform();
  l.thickness = 0.1 + 3 * rng.uniform();
  l.albedo = {rng.uniform(), rng.uniform(), rng.uniform()};
  l.f0 = {rng.uniform(), rng.uniform(), rng.uniform()};
  l.orientation = {rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform()};
  return l;
}

std::vector<std::vector<sg::FlakeLayer>> stacks(mcref::Rng& rng) {
  const auto S = sg::FlakeType::kSurface, F = sg::FlakeType::kFiber;
  return {{random_layer(rng, S)}, {random_layer(rng, F)}, {random_layer(rng, S), random_layer(rng, F)},
          {random_layer(rng, F), random_layer(rng, S)}};
}

sg::MultipleScatteringLobes unmodified(const std::vector<sg::FlakeLayer>& st, double w1, double w2) {
  sg::MultipleScatteringLobes m;
  for (const sg::FlakeLayer& l : st) m.layers.push_back({l.alpha, l.thickness, l.albedo, l.f0});
  m.w1 = w1;
  m.w2 = w2;
  return m;
}

TEST(SggxMultipleScatteringLobes, UnmodifiedWithW1OneW2ZeroIsSingleScattering) {
  mcref::Rng rng(161);  // seed 161, 4 stacks x 500 direction pairs (both sides)
  for (const auto& st : stacks(rng)) {
    const sg::MultipleScatteringLobes m = unmodified(st, 1, 0);
    int transmission = 0;
    for (int n = 0; n < 500; ++n) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      transmission += (wi.z > 0) != (wo.z > 0);
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(sg::multiple_scattering_bsdf(st, m, c, wi, wo), sg::single_scattering_bsdf(sg::flake_stack(st, c), wi, wo));
    }
    EXPECT_GT(transmission, 100);
  }
}

// The modified lobe is the single scattering of a stack built by hand with the
// original type and orientation and the modified alpha, T, gamma, f0.
TEST(SggxMultipleScatteringLobes, ModifiedParametersKeepTypeAndOrientation) {
  mcref::Rng rng(162);
  for (const auto& st : stacks(rng)) {
    sg::MultipleScatteringLobes m = unmodified(st, 0.7, 0.3);
    for (sg::ModifiedLayer& x : m.layers) {
      x.alpha = 0.1 + 0.9 * rng.uniform();
      x.thickness = 0.2 + 5 * rng.uniform();
      x.albedo = {rng.uniform(), rng.uniform(), rng.uniform()};
      x.f0 = {rng.uniform(), rng.uniform(), rng.uniform()};
    }
    m.split = {0.6, 0.25};
    for (int n = 0; n < 200; ++n) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      for (int c = 0; c < 3; ++c) {
        std::vector<sg::Layer> by_hand;
        for (std::size_t k = 0; k < st.size(); ++k) {
          const sg::ModifiedLayer& x = m.layers[k];
          const sg::Sggx s = st[k].type == sg::FlakeType::kFiber ? sg::fiber_like(x.alpha, st[k].orientation)
                                                                 : sg::surface_like(x.alpha, st[k].orientation);
          by_hand.push_back(sg::sggx_layer(x.thickness, st[k].density, s, x.albedo[c], x.f0[c]));
        }
        const double side = (wi.z > 0) == (wo.z > 0) ? 0.6 : 0.25;
        const double expected = 0.7 * sg::single_scattering_bsdf(by_hand, wi, wo) + 0.3 * side / kPi;
        EXPECT_NEAR(sg::multiple_scattering_bsdf(st, m, c, wi, wo), expected, 1e-14 * (1 + expected));
      }
    }
  }
}

// Energy of the Lambertian lobe from wi: integral of f |cos theta_o| over each
// hemisphere (Gauss-Legendre in cos theta_o, the integrand is constant in phi).
TEST(SggxMultipleScatteringLobes, LambertianLobeCarriesItsStatedEnergyPerSide) {
  const mcref::GaussLegendre rule(16);
  for (const sg::LambertianSplit split : {sg::LambertianSplit{1, 1}, sg::LambertianSplit{1, 0}, sg::LambertianSplit{0.3, 0.55}})
    for (const Vec3 wi : {Vec3{0.3, 0.1, 0.9486832980505138}, Vec3{0.6, 0, -0.8}}) {
      double up = 0, down = 0;
      for (double z_sign : {1.0, -1.0}) {
        const double e = 2 * kPi * rule.integrate([&](double mu) {
          const Vec3 wo{std::sqrt(1 - mu * mu), 0, z_sign * mu};
          return sg::lambertian_lobe(split, wi, wo) * mu;
        }, 0, 1);
        (z_sign > 0 ? up : down) = e;
      }
      const double same = wi.z > 0 ? up : down, other = wi.z > 0 ? down : up;
      EXPECT_NEAR(same, split.reflection, 1e-14);
      EXPECT_NEAR(other, split.transmission, 1e-14);
    }
}

TEST(SggxMultipleScatteringLobes, ReciprocalAndLinearInTheWeights) {
  mcref::Rng rng(163);
  for (const auto& st : stacks(rng)) {
    sg::MultipleScatteringLobes m = unmodified(st, 0.8, 0.4);
    m.layers[0].alpha *= 0.5;
    m.layers.back().thickness *= 2;
    m.split = {0.7, 0.2};
    sg::MultipleScatteringLobes only1 = m, only2 = m;
    only1.w2 = 0;
    only2.w1 = 0;
    for (int n = 0; n < 300; ++n) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      for (int c = 0; c < 3; ++c) {
        const double f = sg::multiple_scattering_bsdf(st, m, c, wi, wo);
        EXPECT_NEAR(f, sg::multiple_scattering_bsdf(st, m, c, wo, wi), 1e-12 * (1 + f));
        EXPECT_NEAR(f, sg::multiple_scattering_bsdf(st, only1, c, wi, wo) + sg::multiple_scattering_bsdf(st, only2, c, wi, wo),
                    1e-14 * (1 + f));
      }
      const Rgb rgb = sg::multiple_scattering_bsdf_rgb(st, m, wi, wo);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb[c], sg::multiple_scattering_bsdf(st, m, c, wi, wo));
    }
  }
}

TEST(SggxMultipleScatteringLobes, BadInputNamesTheKey) {
  mcref::Rng rng(164);
  const std::vector<sg::FlakeLayer> st = {random_layer(rng, sg::FlakeType::kSurface)};
  const Vec3 wi{0, 0, 1}, wo{0.6, 0, 0.8};
  auto message = [&](const sg::MultipleScatteringLobes& m) {
    try {
      sg::multiple_scattering_bsdf(st, m, 0, wi, wo);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  sg::MultipleScatteringLobes m = unmodified(st, 1, 0);
  EXPECT_NO_THROW(sg::multiple_scattering_bsdf(st, m, 0, wi, wo));
  sg::MultipleScatteringLobes bad = m;
  bad.w2 = -1;
  EXPECT_NE(message(bad).find("w2 = -1"), std::string::npos) << message(bad);
  bad = m;
  bad.layers[0].albedo = {0.5, 1.5, 0.5};
  EXPECT_NE(message(bad).find("layers[0].albedo[1] = 1.5"), std::string::npos) << message(bad);
  EXPECT_NE(message(bad).find("[0, 1]"), std::string::npos);
  bad = m;
  bad.layers.push_back(m.layers[0]);
  EXPECT_NE(message(bad).find("layers (count) = 2"), std::string::npos) << message(bad);
  bad = m;
  bad.layers[0].alpha = 0;
  EXPECT_NE(message(bad).find("layers[0].alpha = 0"), std::string::npos) << message(bad);
  EXPECT_THROW(sg::multiple_scattering_bsdf(st, m, 3, wi, wo), std::invalid_argument);
  std::vector<sg::FlakeLayer> bad_stack = st;
  bad_stack[0].albedo = {2, 0.5, 0.5};
  try {
    sg::multiple_scattering_bsdf(bad_stack, m, 0, wi, wo);
    ADD_FAILURE() << "no error for albedo 2";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("layer 0: albedo[0] = 2"), std::string::npos) << e.what();
  }
}

}  // namespace
