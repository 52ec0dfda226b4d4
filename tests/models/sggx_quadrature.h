#pragma once
// Tensor Gauss-Legendre quadrature over the sphere in polar coordinates around
// a chosen pole (test helper). Choosing the pole at a point singularity of the
// integrand (e.g. o = -i for the flake phase function) makes it smooth in
// (theta', phi'); an even panel count in theta' puts a panel edge on the
// equator, where <pole.m>^+ has its kink.
#include <cmath>

#include "models/core/frame.h"
#include "models/core/quadrature.h"
#include "models/core/vec.h"

namespace mcref::sggx_test {

// \int f(w) dw over theta' in [0, theta_max] around `pole`, all phi'.
template <class F>
double integrate_sphere(F&& f, Vec3 pole, int theta_panels, int phi_panels, int points = 8,
                        double theta_max = kPi) {
  const GaussLegendre rule(points);
  const Frame frame(normalize(pole));
  const double ht = theta_max / theta_panels, hp = 2 * kPi / phi_panels;
  double total = 0;
  for (int a = 0; a < theta_panels; ++a)
    total += rule.integrate([&](double t) {
      const double st = std::sin(t), ct = std::cos(t);
      double ring = 0;
      for (int b = 0; b < phi_panels; ++b)
        ring += rule.integrate([&](double p) {
          return f(frame.to_world({st * std::cos(p), st * std::sin(p), ct}));
        }, b * hp, (b + 1) * hp);
      return ring * st;
    }, a * ht, (a + 1) * ht);
  return total;
}

}  // namespace mcref::sggx_test

namespace mcref::sggx_test {

// \int f(w) dw over the hemisphere {w.z * side > 0} (side = +1 or -1), in
// polar coordinates around `pole`, which must lie strictly inside it. The
// theta' limit follows the horizon for each phi', so a kink of the integrand
// at z = 0 sits on the domain boundary, and a point singularity at the pole
// (o = -wi for flake transmission) is smoothed by the polar map.
template <class F>
double integrate_hemisphere_around(F&& f, Vec3 pole, double side, int theta_panels, int phi_panels,
                                   int points = 8) {
  const GaussLegendre rule(points);
  const Frame frame(normalize(pole));
  const double hp = 2 * kPi / phi_panels;
  const double pz = side * frame.n.z;  // > 0 inside
  double total = 0;
  for (int b = 0; b < phi_panels; ++b)
    total += rule.integrate([&](double p) {
      const Vec3 e = frame.to_world({std::cos(p), std::sin(p), 0});
      // w(t).z * side = pz cos t + ez sin t vanishes at t = atan2(pz, -ez).
      const double tmax = std::atan2(pz, -side * e.z);
      const double ht = tmax / theta_panels;
      double line = 0;
      for (int a = 0; a < theta_panels; ++a)
        line += rule.integrate([&](double t) {
          return f(frame.n * std::cos(t) + e * std::sin(t)) * std::sin(t);
        }, a * ht, (a + 1) * ht);
      return line;
    }, b * hp, (b + 1) * hp);
  return total;
}

}  // namespace mcref::sggx_test
