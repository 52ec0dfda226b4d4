// SpongeCake single scattering (Eq. 8-16, Sec. 4.4-4.5): closed forms of G,
// the isotropic half-space limit (Eq. 13), agreement with direct quadrature of
// the defining depth integral for multi-layer stacks (reflection and
// transmission, light from either side), reciprocity, layer splitting, and
// energy against both a closed form and a single-scattering Monte Carlo.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/core/warp.h"
#include "models/sggx/single_scattering.h"
#include "tests/models/sggx_quadrature.h"

namespace {

using mcref::Vec3;
using mcref::kPi;
namespace sg = mcref::sggx;
namespace mt = mcref::sggx_test;
using Stack = std::vector<sg::Layer>;

Vec3 dir(double theta, double phi) { return mcref::spherical_direction(theta, phi); }

// Three different media, anisotropic and tilted, so that no symmetry hides errors.
Stack mixed_stack() {
  return {sg::sggx_layer(0.5, 1.2, sg::surface_like(0.4, {0.3, 0, 1}), 0.9, 0.2),
          sg::hg_layer(0.3, 2.0, 0.6, 0.8),
          sg::sggx_layer(1.0, 1.0, sg::fiber_like(0.5, {1, 0, 0.2}), 1.0, 1.0)};
}

// The defining integral (Eq. 8 / 15) by Gauss-Legendre over the depth of the
// scattering vertex, with optical depths accumulated from the layer list for
// each depth (no closed-form G, no per-layer attenuation bookkeeping).
// Depth t runs from the face the light enters; 8 panels x 16 points per layer
// integrate these exponentials (exponent range < 40 per layer) to ~1e-14.
double depth_integral_reference(const Stack& stack, Vec3 wi, Vec3 wo) {
  const double mi = std::fabs(wi.z), mo = std::fabs(wo.z);
  const bool from_top = wi.z > 0, reflection = (wi.z > 0) == (wo.z > 0);
  std::vector<const sg::Layer*> order;
  for (std::size_t s = 0; s < stack.size(); ++s) order.push_back(&stack[from_top ? s : stack.size() - 1 - s]);
  auto optical = [&](double t, Vec3 w) {  // optical depth along w from the entry face to depth t
    double d = 0, start = 0;
    for (const sg::Layer* l : order) {
      const double overlap = std::fmax(0.0, std::fmin(t, start + l->thickness) - start);
      d += l->density * l->sigma(w) * overlap / std::fabs(w.z);
      start += l->thickness;
    }
    return d;
  };
  double total_depth = 0;
  for (const sg::Layer* l : order) total_depth += l->thickness;
  const double exit_o = optical(total_depth, wo);
  double result = 0, start = 0;
  for (const sg::Layer* l : order) {
    const double kernel = l->density * l->reduced_phase(wi, wo) / (mi * mo);  // fhat_p / (mu_i mu_o)
    result += mcref::integrate_composite([&](double t) {
      const double along_o = reflection ? optical(t, wo) : exit_o - optical(t, wo);
      return kernel * std::exp(-optical(t, wi) - along_o);
    }, start, start + l->thickness, 8, 16);
    start += l->thickness;
  }
  return result;
}

TEST(sggxSingleScattering, GClosedFormsMatchDepthIntegrals) {
  for (double tau : {0.01, 0.7, 5.0})
    for (double li : {0.3, 1.0, 4.0})
      for (double lo : {0.5, 1.0, 1.0 + 1e-9, 7.0}) {
        const double r = mcref::integrate_composite([&](double x) { return std::exp(-x * (li + lo)); }, 0, tau, 8, 16);
        const double t = mcref::integrate_composite(
            [&](double x) { return std::exp(-x * li - (tau - x) * lo); }, 0, tau, 8, 16);
        EXPECT_NEAR(sg::reflection_G(tau, li, lo), r, 1e-13 * r);
        EXPECT_NEAR(sg::transmission_G(tau, li, lo), t, 1e-13 * t) << tau << " " << li << " " << lo;
        if (std::fabs(li - lo) > 1e-3) {  // Eq. 16 as printed, signed Lambda_o = -lo
          EXPECT_NEAR(sg::transmission_G_eq16_as_printed(tau, li, -lo), t, 1e-12 * t);
        }
      }
  // The limit Lambda_i = Lambda_o: tau exp(-tau L); the printed Eq. 16 is 0/0 there.
  EXPECT_NEAR(sg::transmission_G(2.0, 1.5, 1.5), 2.0 * std::exp(-3.0), 1e-15);
  EXPECT_TRUE(std::isnan(sg::transmission_G_eq16_as_printed(2.0, 1.5, -1.5)));
  // Half-space limits.
  const double inf = INFINITY;
  EXPECT_DOUBLE_EQ(sg::reflection_G(inf, 0.5, 1.5), 0.5);
  EXPECT_EQ(sg::transmission_G(inf, 0.5, 1.5), 0.0);
}

TEST(sggxSingleScattering, IsotropicHalfSpaceEq13) {
  // alpha = 1 flakes (D = 1/pi, sigma = 1, f_p = 1/(4 pi)) with F = a (f0 = 1),
  // isotropic and g = 0 HG media: f_r = a / (4 pi (mu_i + mu_o)), with T = inf
  // and with T rho = 1000 (e^-1000 = 0 in double).
  const double a = 0.7, inf = INFINITY;
  const std::vector<Stack> stacks = {
      {sg::sggx_layer(inf, 1.0, sg::surface_like(1.0, {0.2, 0.5, 1}), a, 1.0)},
      {sg::sggx_layer(1000.0, 1.0, sg::fiber_like(1.0, {0, 0, 1}), a, 1.0)},
      {sg::isotropic_layer(inf, 3.0, a)},
      {sg::hg_layer(250.0, 4.0, 0.0, a)}};
  for (const Stack& s : stacks)
    for (double ti : {0.0, 0.5, 1.2, 1.5})
      for (double to : {0.1, 0.9, 1.5}) {
        const Vec3 wi = dir(ti, 0.3), wo = dir(to, 2.5);
        const double expected = a / (4 * kPi * (wi.z + wo.z));
        EXPECT_NEAR(sg::single_scattering_reflection(s, wi, wo), expected, 1e-13 * expected);
        EXPECT_EQ(sg::single_scattering_transmission(s, wi, -wo), 0.0);
      }
  // Finite isotropic slab (Hanrahan & Krueger 1993): a (1 - e^{-tau(1/mu_i + 1/mu_o)}) / (4 pi (mu_i + mu_o)).
  const Stack slab = {sg::isotropic_layer(0.5, 1.5, a)};
  const Vec3 wi = dir(0.4, 0), wo = dir(1.1, 1);
  const double hk = a * (1 - std::exp(-0.75 * (1 / wi.z + 1 / wo.z))) / (4 * kPi * (wi.z + wo.z));
  EXPECT_NEAR(sg::single_scattering_reflection(slab, wi, wo), hk, 1e-14);
}

TEST(sggxSingleScattering, MatchesDepthIntegralForStacks) {
  const Stack stack = mixed_stack();
  mcref::Rng rng(17);
  int checked = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    const Vec3 wo = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    if (std::fabs(wi.z) < 0.05 || std::fabs(wo.z) < 0.05) continue;
    const double ref = depth_integral_reference(stack, wi, wo);
    const double f = sg::single_scattering_bsdf(stack, wi, wo);
    EXPECT_NEAR(f, ref, 1e-11 * ref + 1e-300) << "wi.z=" << wi.z << " wo.z=" << wo.z;
    const bool same = (wi.z > 0) == (wo.z > 0);
    EXPECT_EQ(sg::single_scattering_reflection(stack, wi, wo), same ? f : 0.0);
    EXPECT_EQ(sg::single_scattering_transmission(stack, wi, wo), same ? 0.0 : f);
    ++checked;
  }
  EXPECT_GT(checked, 300);
  // Transmission with Lambda_i = Lambda_o in an isotropic-extinction stack (HG/isotropic:
  // sigma = 1, so equal |cos|): the limit of Eq. 16.
  const Stack hg = {sg::hg_layer(0.4, 1.0, 0.3, 0.9), sg::isotropic_layer(0.6, 2.0, 0.5)};
  const Vec3 wi = dir(0.8, 0.0), wo = dir(kPi - 0.8, 1.0);
  const double ref = depth_integral_reference(hg, wi, wo);
  EXPECT_NEAR(sg::single_scattering_transmission(hg, wi, wo), ref, 1e-12 * ref);
}

TEST(sggxSingleScattering, Reciprocity) {
  const Stack tilted = mixed_stack();
  const Stack azimuthal = {sg::sggx_layer(0.7, 1.0, sg::surface_like(0.3, {0, 0, 1}), 0.8, 0.05),
                           sg::sggx_layer(2.0, 0.5, sg::fiber_like(0.6, {0, 0, 1}), 0.9, 1.0)};
  mcref::Rng rng(23);
  for (const Stack* s : {&azimuthal, &tilted})
    for (int k = 0; k < 200; ++k) {
      const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
      const Vec3 wo = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
      const double a = sg::single_scattering_bsdf(*s, wi, wo), b = sg::single_scattering_bsdf(*s, wo, wi);
      EXPECT_NEAR(a, b, 1e-12 * a);
      const double da = sg::delta_transmittance(*s, wi), db = sg::delta_transmittance(*s, -wi);
      EXPECT_NEAR(da, db, 1e-15);
    }
}

TEST(sggxSingleScattering, SplittingALayerChangesNothing) {
  const Stack whole = mixed_stack();
  Stack split = whole;
  sg::Layer half = split[1];
  half.thickness *= 0.5;
  split[1] = half;
  split.insert(split.begin() + 1, half);
  mcref::Rng rng(29);
  for (int k = 0; k < 200; ++k) {
    const Vec3 wi = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    const Vec3 wo = mcref::sample_uniform_sphere(rng.uniform(), rng.uniform());
    const double a = sg::single_scattering_bsdf(whole, wi, wo), b = sg::single_scattering_bsdf(split, wi, wo);
    EXPECT_NEAR(a, b, 1e-12 * a);
    EXPECT_NEAR(sg::delta_transmittance(whole, wi), sg::delta_transmittance(split, wi), 1e-15);
  }
}

TEST(sggxSingleScattering, DeltaAndSubstrateTerms) {
  const Stack stack = mixed_stack();
  const Vec3 wi = dir(0.6, 0.2), wo = dir(1.0, 2.0);
  double depth_i = 0, depth_o = 0;
  for (const sg::Layer& l : stack) {
    depth_i += l.thickness * l.density * l.sigma(wi) / wi.z;
    depth_o += l.thickness * l.density * l.sigma(wo) / wo.z;
  }
  EXPECT_NEAR(sg::delta_transmittance(stack, wi), std::exp(-depth_i), 1e-15);
  EXPECT_NEAR(sg::lambertian_substrate_term(stack, wi, wo, 0.6), 0.6 / kPi * std::exp(-depth_i - depth_o), 1e-15);
  EXPECT_EQ(sg::lambertian_substrate_term(stack, wi, -wo, 0.6), 0.0);
  EXPECT_NEAR(sg::lambertian_substrate_term({}, wi, wo, 0.6), 0.6 / kPi, 1e-15);
  EXPECT_EQ(sg::delta_transmittance(stack, {1, 0, 0}), 0.0);
  EXPECT_EQ(sg::single_scattering_bsdf(stack, {1, 0, 0}, wo), 0.0);
}

// Energy of the single-scattering BSDF for incidence wi, by quadrature over wo:
// reflection around +-z, transmission around -wi (the flakes' singular point).
double single_scattering_energy(const Stack& s, Vec3 wi, double substrate_albedo, int tp, int pp) {
  const double side = wi.z > 0 ? 1 : -1;
  const double refl = mt::integrate_hemisphere_around(
      [&](Vec3 wo) {
        return (sg::single_scattering_reflection(s, wi, wo) +
                sg::lambertian_substrate_term(s, wi, wo, substrate_albedo)) * std::fabs(wo.z);
      }, {0, 0, side}, side, tp, pp);
  const double trans = mt::integrate_hemisphere_around(
      [&](Vec3 wo) { return sg::single_scattering_transmission(s, wi, wo) * std::fabs(wo.z); }, -wi, -side, tp, pp);
  return refl + trans;
}

TEST(sggxSingleScattering, HalfSpaceEnergyClosedForm) {
  // \int a/(4 pi (mu_i + mu_o)) mu_o dwo = (a/2)(1 - mu_i ln(1 + 1/mu_i)).
  const double a = 0.9;
  const Stack s = {sg::sggx_layer(INFINITY, 1.0, sg::surface_like(1.0, {0, 0, 1}), a, 1.0)};
  for (double ti : {0.0, 0.7, 1.3}) {
    const double mu = std::cos(ti);
    const double exact = 0.5 * a * (1 - mu * std::log(1 + 1 / mu));
    EXPECT_NEAR(single_scattering_energy(s, dir(ti, 0.4), 0, 32, 64), exact, 1e-8);
  }
}

// Single-scattering Monte Carlo: first collision depth sampled exactly along wi,
// phase sampled with Layer::sample_phase, escape attenuation along wo; or one
// Lambertian substrate bounce for unscattered light. Independent of G.
struct McEstimate { double mean, stderr_; };
McEstimate single_scattering_mc(const Stack& stack, Vec3 wi, double substrate_albedo, long n, std::uint64_t seed) {
  const bool from_top = wi.z > 0;
  std::vector<const sg::Layer*> order;
  for (std::size_t s = 0; s < stack.size(); ++s) order.push_back(&stack[from_top ? s : stack.size() - 1 - s]);
  auto depth = [](const sg::Layer* l, Vec3 w) { return l->optical_thickness() * l->sigma(w) / std::fabs(w.z); };
  mcref::Rng rng(seed);
  double sum = 0, sum2 = 0;
  for (long k = 0; k < n; ++k) {
    double s = -std::log1p(-rng.uniform()), score = 0;
    std::size_t hit = order.size();
    double frac = 0;
    for (std::size_t j = 0; j < order.size(); ++j) {
      const double d = depth(order[j], wi);
      if (s < d) { hit = j; frac = s / d; break; }
      s -= d;
    }
    const double u1 = rng.uniform(), u2 = rng.uniform();
    if (hit < order.size()) {
      const sg::PhaseSample ps = order[hit]->sample_phase(wi, u1, u2);
      if (ps.valid && ps.wo.z != 0) {
        const bool back = (ps.wo.z > 0) == from_top;
        double esc = (back ? frac : 1 - frac) * depth(order[hit], ps.wo);
        for (std::size_t j = 0; j < order.size(); ++j)
          if (back ? j < hit : j > hit) esc += depth(order[j], ps.wo);
        score = ps.weight * std::exp(-esc);
      }
    } else if (from_top && substrate_albedo > 0) {
      const Vec3 wo = mcref::sample_cosine_hemisphere(u1, u2);
      score = substrate_albedo * sg::delta_transmittance(stack, wo);
    }
    sum += score;
    sum2 += score * score;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::fmax(0.0, sum2 / n - mean * mean) / (n - 1))};
}

TEST(sggxSingleScattering, EnergyMatchesMonteCarloAndIsBelowOne) {
  // Tolerance: 4.5 standard errors of the 10^6-path estimate plus the
  // quadrature error, bounded by the difference of two resolutions.
  const Stack stack = mixed_stack();
  const Stack white = {sg::sggx_layer(0.8, 1.0, sg::surface_like(0.5, {0.2, 0, 1}), 1.0, 1.0),
                       sg::sggx_layer(1.5, 1.0, sg::fiber_like(0.7, {0, 1, 0.3}), 1.0, 1.0)};
  struct Run { const Stack* s; Vec3 wi; double substrate; };
  const std::vector<Run> runs = {{&stack, dir(0.3, 0.1), 0.5}, {&stack, dir(1.2, 2.0), 0.0},
                                 {&stack, dir(2.2, 4.0), 0.0}, {&white, dir(0.9, 1.0), 0.0}};
  std::uint64_t seed = 100;
  for (const Run& r : runs) {
    const double fine = single_scattering_energy(*r.s, r.wi, r.substrate, 32, 64);
    const double coarse = single_scattering_energy(*r.s, r.wi, r.substrate, 24, 48);
    const McEstimate mc = single_scattering_mc(*r.s, r.wi, r.substrate, 1000000, seed++);
    EXPECT_NEAR(fine, mc.mean, 4.5 * mc.stderr_ + 2 * std::fabs(fine - coarse))
        << "wi.z=" << r.wi.z << " quadrature " << fine << " (coarse " << coarse << ") MC " << mc.mean << " +- "
        << mc.stderr_;
    // Only light that interacts can be single-scattered: E < 1 - T_delta(wi).
    EXPECT_LT(fine, 1 - sg::delta_transmittance(*r.s, r.wi));
    std::printf("wi.z = %+.3f: quadrature %.6f (coarse %.6f), Monte Carlo %.6f +- %.6f\n", r.wi.z, fine, coarse,
                mc.mean, mc.stderr_);
  }
}

}  // namespace
