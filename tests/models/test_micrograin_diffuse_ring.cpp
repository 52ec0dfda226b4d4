// models/micrograin/diffuse_ring.h: the ring integral of the G_dist diffuse
// geometry, with Fresnel and for anisotropic grains, against an independent
// high-resolution reference: the integrand written with vectors (<d.m> of the
// normalised real normal), the zeros found by half_angle_zeros.h, and each
// piece in 64 panels of 20-point Gauss-Legendre (exact to rounding for these
// analytic pieces: 12-point panels agree with it to ~1e-15 of the ring).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/microfacet/fresnel.h"
#include "models/micrograin/diffuse_ring.h"
#include "models/micrograin/unit_space.h"
#include "tests/models/half_angle_zeros.h"

using namespace mcref;
using namespace mcref::micrograin;

namespace {

double reference_ring(const GrainField& f, Vec3 i, Vec3 o, double ior, double h, double st, int points = 20) {
  const auto integrand = [&](double a) {
    const Vec3 mm{st * f.beta_x * std::cos(a), st * f.beta_y * std::sin(a), h};  // M m'
    const double len = std::sqrt(dot(mm, mm));
    const Vec3 m = mm / len;
    const double im = dot(i, m), om = dot(o, m);
    if (im <= 0 || om <= 0) return 0.0;
    const double t = ior > 1 ? (1 - fresnel_dielectric(im, ior)) * (1 - fresnel_dielectric(om, ior)) : 1.0;
    return im * om * t * len;
  };
  std::vector<double> cuts{0.0, 2 * kPi};
  add_half_angle_zeros({h * i.z, st * f.beta_x * i.x, st * f.beta_y * i.y}, cuts);
  add_half_angle_zeros({h * o.z, st * f.beta_x * o.x, st * f.beta_y * o.y}, cuts);
  std::sort(cuts.begin(), cuts.end());
  const GaussLegendre g(points);
  const int panels = 64;
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double w = (cuts[k + 1] - cuts[k]) / panels;
    for (int p = 0; p < panels; ++p) sum += g.integrate(integrand, cuts[k] + p * w, cuts[k] + (p + 1) * w);
  }
  return sum;
}

// An upper bound of the unclipped integrand's integral, 2 pi max|P_i| max|P_o| / min |M m'|:
// the scale of rounding on the ring.
double unclipped_scale(const GrainField& f, Vec3 i, Vec3 o, double h, double st) {
  const auto amplitude = [&](Vec3 d) { return std::fabs(h * d.z) + st * std::hypot(f.beta_x * d.x, f.beta_y * d.y); };
  return 2 * kPi * amplitude(i) * amplitude(o) / std::hypot(st * std::min(f.beta_x, f.beta_y), h);
}

}  // namespace

// The reference's own error: 12-point panels agree with the 20-point ones to far
// below the tolerance used below (so the reference is exact to rounding).
TEST(MicrograinDiffuseRing, ReferenceConverged) {
  const GrainField f{0.5, 0.4, 1.7};
  const Vec3 i = spherical_direction(1.4, 0.3), o = spherical_direction(0.9, 2.0);
  const double r20 = reference_ring(f, i, o, 1.5, 0.3, std::sqrt(1 - 0.09)),
               r12 = reference_ring(f, i, o, 1.5, 0.3, std::sqrt(1 - 0.09), 12);
  EXPECT_GT(r20, 0.1);
  EXPECT_NEAR(r12, r20, 1e-14 * r20);
}

// Seed 77, 6000 random rings: beta_x, beta_y log-uniform in [0.2, 3] (every
// other field isotropic), ior in {1.33, 1.5, 2.4} or none (anisotropic grains
// only: isotropic ones without Fresnel are in closed form), directions with
// cos theta uniform, and rings of four kinds: any theta'; near-tangent to i's
// ring (theta' within 1e-9..1e-3 of pi/2 - theta'_i, either side); grazing
// directions (theta within 1e-9..1e-4 of pi/2); the equator (theta' = pi/2,
// h = 0) or within 1e-9 of it. Tolerance 1e-10 of the ring's value, plus
// 1e-14 of its unclipped scale (rounding of the near-empty rings).
TEST(MicrograinDiffuseRing, MatchesHighResolutionReference) {
  Rng rng(77);
  const double iors[] = {1.33, 1.5, 2.4, 0.0};
  int nonzero = 0, near_tangent = 0, grazing = 0;
  for (int k = 0; k < 6000; ++k) {
    const double bx = 0.2 * std::pow(15.0, rng.uniform());
    const GrainField f{0.5, bx, k % 2 == 0 ? bx : 0.2 * std::pow(15.0, rng.uniform())};
    const double ior = iors[static_cast<int>(rng.uniform() * (f.beta_x == f.beta_y ? 3 : 4))];
    double theta_i = std::acos(rng.uniform()), theta_o = std::acos(rng.uniform());
    const int kind = (k / 4) % 4;
    if (kind == 2) {
      theta_i = kPi / 2 - std::pow(10.0, -9 + 5 * rng.uniform());
      if (rng.uniform() < 0.5) theta_o = kPi / 2 - std::pow(10.0, -9 + 5 * rng.uniform());
    }
    const Vec3 i = spherical_direction(theta_i, 2 * kPi * rng.uniform()),
               o = spherical_direction(theta_o, 2 * kPi * rng.uniform());
    double theta = 0.5 * kPi * rng.uniform();
    if (kind == 1) {
      const double tangent = kPi / 2 - spherical_theta(to_unit_direction(f, i));
      theta = std::clamp(tangent + std::copysign(std::pow(10.0, -9 + 6 * rng.uniform()), rng.uniform() - 0.5), 0.0,
                         kPi / 2);
    }
    if (kind == 3) theta = rng.uniform() < 0.5 ? kPi / 2 : kPi / 2 - 1e-9;
    const double h = theta == kPi / 2 ? 0.0 : std::cos(theta), st = std::sin(theta);
    const double q = diffuse_ring_integral(f, i, o, ior, h, st), r = reference_ring(f, i, o, ior, h, st);
    const double scale = unclipped_scale(f, i, o, h, st);
    ASSERT_NEAR(q, r, 1e-10 * r + 1e-14 * scale)
        << k << ": beta " << f.beta_x << " " << f.beta_y << ", ior " << ior << ", theta_i " << theta_i << ", theta_o "
        << theta_o << ", theta' " << theta;
    if (r > 1e-3 * scale) {
      ++nonzero;
      near_tangent += kind == 1;
      grazing += kind == 2;
    }
  }
  // Not mostly 0 against 0, in every kind of ring.
  EXPECT_GT(nonzero, 2000);
  EXPECT_GT(near_tangent, 300);
  EXPECT_GT(grazing, 300);
}
