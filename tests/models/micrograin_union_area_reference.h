#pragma once
// Test reference for cap_shadow_union_area (models/micrograin/two_way_masking.h):
// the former model, 1/2 ∮ (max(r_i, r_o)^2 - (1 - h^2)) dpsi by adaptive Gauss-Legendre
// between the kinks (where a radius leaves the disc) and the crossings r_i = r_o
// found on a grid of `grid` points in psi and refined by the Illinois method.
// Absolute tolerance tol times the area's scale (1 + a 10-point estimate). The
// model used grid = 48 and tol = 1e-10; a crossing missed by that grid (e.g. one
// next to a kink, theta_i = 10, theta_o = 60 deg, 1 deg apart, h = 0) can leave the
// adaptive rule off by 1.5e-8 (a kink inside a piece), so the tests use a finer grid.
#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"

namespace mcref::micrograin::test {

struct RefDir {
  double s, c, phi;  // sin, cos and azimuth of a unit-space direction
};

inline RefDir ref_dir(Vec3 d) {
  const double s = std::hypot(d.x, d.y), n = std::hypot(s, d.z);
  return {s / n, d.z / n, std::atan2(d.y, d.x)};
}

// Radius of K_d(h) at azimuth psi, u = sin theta_d cos(psi - phi_d):
//   r_c = (-u h cos theta_d + sqrt(1 - u^2 - h^2 (sin^2 theta_d - u^2))) / (1 - u^2)
// if r_c u > h cos theta_d (the cylinder part), else sqrt(1 - h^2) (the sphere at p).
inline double ref_radius(const RefDir& d, double h, double psi) {
  const double rs = std::sqrt(std::max(0.0, 1 - h * h));
  const double x = psi - d.phi, cx = std::cos(x), sx = std::sin(x);
  const double u = d.s * cx;
  if (u <= 0) return rs;
  const double w = d.c * d.c * cx * cx + sx * sx;
  const double disc = w * rs * rs + h * h * d.c * d.c;
  const double rc = (-u * h * d.c + std::sqrt(disc)) / w;
  return rc * u > h * d.c ? std::max(rs, rc) : rs;
}

// Azimuths where d's radius leaves the disc: u sqrt(1 - h^2) = h cos theta_d.
inline void ref_kinks(const RefDir& d, double h, std::vector<double>& cuts) {
  if (d.s <= 0) return;
  const double k = h * d.c / (d.s * std::sqrt(std::max(1e-300, 1 - h * h)));
  if (k >= 1) return;  // h >= sin theta_d: no shadow beyond the disc
  const double a = std::acos(k);
  cuts.push_back(d.phi - a);
  cuts.push_back(d.phi + a);
}

inline double union_area_adaptive(Vec3 i_unit, Vec3 o_unit, double h, double tol = 1e-10, int grid = 48) {
  const RefDir d_i = ref_dir(i_unit), d_o = ref_dir(o_unit);
  const double rs2 = std::max(0.0, 1 - h * h);
  auto excess = [&](double psi) {
    const double r = std::max(ref_radius(d_i, h, psi), ref_radius(d_o, h, psi));
    return 0.5 * (r * r - rs2);
  };
  const double psi0 = d_i.phi - kPi;
  std::vector<double> cuts{psi0, psi0 + 2 * kPi};
  std::vector<double> kinks;
  ref_kinks(d_i, h, kinks);
  ref_kinks(d_o, h, kinks);
  if (kinks.empty()) return 0.0;  // both radii are the disc's
  for (double k : kinks) cuts.push_back(psi0 + std::fmod(std::fmod(k - psi0, 2 * kPi) + 2 * kPi, 2 * kPi));
  auto diff = [&](double psi) { return ref_radius(d_i, h, psi) - ref_radius(d_o, h, psi); };
  double a = psi0, fa = diff(psi0);
  for (int k = 1; k <= grid; ++k) {
    const double b = psi0 + 2 * kPi * k / grid, fb = diff(b);
    if ((fa > 0 && fb < 0) || (fa < 0 && fb > 0)) {
      double lo = a, hi = b, flo = fa, fhi = fb;
      int side = 0;
      for (int it = 0; it < 100 && hi - lo > 1e-14; ++it) {
        const double x = (lo * fhi - hi * flo) / (fhi - flo), fx = diff(x);
        if (fx == 0) {
          lo = hi = x;
          break;
        }
        if ((fx > 0) == (flo > 0)) {
          lo = x;
          flo = fx;
          if (side == -1) fhi *= 0.5;
          side = -1;
        } else {
          hi = x;
          fhi = fx;
          if (side == 1) flo *= 0.5;
          side = 1;
        }
      }
      cuts.push_back(0.5 * (lo + hi));
    }
    if (fb != 0) {
      a = b;
      fa = fb;
    }
  }
  std::sort(cuts.begin(), cuts.end());
  static const GaussLegendre g(10);
  double scale = 1;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    if (cuts[k + 1] - cuts[k] > 1e-15) scale += std::fabs(g.integrate(excess, cuts[k], cuts[k + 1]));
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    if (hi - lo <= 1e-15) continue;
    sum += integrate_adaptive(excess, lo, hi, tol * scale / cuts.size());
  }
  return sum;
}

}  // namespace mcref::micrograin::test
