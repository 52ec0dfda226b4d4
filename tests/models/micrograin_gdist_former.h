#pragma once
// Benchmark reference for gdist_diffuse_geometry (models/micrograin/micrograin_bsdf.h):
// the former rule (main 0992240), kept to time the current one against it. The
// ring split at a = 0 and at the zeros of P_i, P_o, a 16-point rule per piece
// setting the scale, then adaptive 10-point Gauss-Legendre to rel_tol of it per
// piece; the polar pieces likewise, graded toward their ends; no rounding floor
// (a direction within ~1e-8 rad of grazing refines for ever).
#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/graded_quadrature.h"
#include "models/core/quadrature.h"
#include "models/microfacet/fresnel.h"
#include "models/micrograin/clipped_cosines.h"
#include "models/micrograin/height_masking.h"
#include "models/micrograin/micrograin_bsdf.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/two_way_masking.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin::test {

inline double former_diffuse_geometry(const GrainField& f, Vec3 i, Vec3 o, double ior, TwoWay masking,
                                      double rel_tol = 1e-8) {
  static const GaussLegendre rule(16);
  const bool fresnel = ior > 1;
  auto ring_integral = [&](double h, double st) {
    const Sinusoid p_i{h * i.z, st * f.beta_x * i.x, st * f.beta_y * i.y}, p_o{h * o.z, st * f.beta_x * o.x, st * f.beta_y * o.y};
    if (!fresnel && f.beta_x == f.beta_y) return clipped_product_integral(p_i, p_o) / std::hypot(st * f.beta_x, h);
    std::vector<double> cuts_a{0.0, 2 * kPi};
    add_sinusoid_zeros(p_i, cuts_a);
    add_sinusoid_zeros(p_o, cuts_a);
    std::sort(cuts_a.begin(), cuts_a.end());
    auto integrand = [&](double a) {
      const Vec3 mm{st * std::cos(a) * f.beta_x, st * std::sin(a) * f.beta_y, h};  // M m'
      const double len = std::sqrt(dot(mm, mm)), im = dot(i, mm) / len, om = dot(o, mm) / len;
      if (im <= 0 || om <= 0) return 0.0;
      const double t = fresnel ? (1 - fresnel_dielectric(im, ior)) * (1 - fresnel_dielectric(om, ior)) : 1.0;
      return len * im * om * t;
    };
    double coarse = 0, ring = 0;
    for (std::size_t c = 0; c + 1 < cuts_a.size(); ++c)
      if (cuts_a[c + 1] - cuts_a[c] > 1e-14) coarse += std::fabs(rule.integrate(integrand, cuts_a[c], cuts_a[c + 1]));
    for (std::size_t c = 0; c + 1 < cuts_a.size(); ++c)
      if (cuts_a[c + 1] - cuts_a[c] > 1e-14)
        ring += integrate_adaptive(integrand, cuts_a[c], cuts_a[c + 1], rel_tol * coarse / cuts_a.size() + 1e-300);
    return ring;
  };
  auto polar = [&](double th) {
    const double h = std::cos(th), st = std::sin(th);
    const double g2 = masking == TwoWay::Union ? distant_masking_union(f, i, o, h)
                                               : distant_masking(f, i, h) * distant_masking(f, o, h);
    return st * unit_ndf(f.tau0, h) * ring_integral(h, st) * g2;
  };
  const double ti = spherical_theta(to_unit_direction(f, i)), to = spherical_theta(to_unit_direction(f, o));
  const double cuts[] = {0.0, kPi / 2 - std::max(ti, to), kPi / 2 - std::min(ti, to), kPi / 2};
  double coarse = 0, sum = 0;
  for (int c = 0; c < 3; ++c)
    if (cuts[c + 1] - cuts[c] > 1e-12) coarse += std::fabs(rule.integrate(polar, cuts[c], cuts[c + 1]));
  for (int c = 0; c < 3; ++c)
    if (cuts[c + 1] - cuts[c] > 1e-12) sum += integrate_adaptive_graded(polar, cuts[c], cuts[c + 1], rel_tol * coarse / 3 + 1e-300);
  return f.tau0 * sum / (kPi * i.z * o.z);
}

}  // namespace mcref::micrograin::test
