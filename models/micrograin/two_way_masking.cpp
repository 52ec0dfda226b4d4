#include "models/micrograin/two_way_masking.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {

struct Dir {
  double s, c, phi;  // sin, cos and azimuth of a unit-space direction
};

Dir dir_of(Vec3 d) {
  const double s = std::hypot(d.x, d.y), n = std::hypot(s, d.z);
  return {s / n, d.z / n, std::atan2(d.y, d.x)};
}

double radius(const Dir& d, double h, double psi) {
  const double rs = std::sqrt(std::max(0.0, 1 - h * h));
  const double x = psi - d.phi, cx = std::cos(x), sx = std::sin(x);
  const double u = d.s * cx;
  if (u <= 0) return rs;
  // 1 - u^2 = cos^2 theta cos^2 x + sin^2 x and disc = (1 - u^2)(1 - h^2) + h^2 cos^2 theta,
  // written without the cancellation of 1 - u^2 near grazing (u -> 1).
  const double w = d.c * d.c * cx * cx + sx * sx;
  const double disc = w * rs * rs + h * h * d.c * d.c;
  const double rc = (-u * h * d.c + std::sqrt(disc)) / w;
  return rc * u > h * d.c ? std::max(rs, rc) : rs;
}

// Azimuths where d's radius leaves the disc: u sqrt(1 - h^2) = h cos theta_d.
void add_kinks(const Dir& d, double h, std::vector<double>& cuts) {
  if (d.s <= 0) return;
  const double k = h * d.c / (d.s * std::sqrt(std::max(1e-300, 1 - h * h)));
  if (k >= 1) return;  // h >= sin theta_d: no shadow beyond the disc
  const double a = std::acos(k);
  cuts.push_back(d.phi - a);
  cuts.push_back(d.phi + a);
}

}  // namespace

double shadow_set_radius(Vec3 d_unit, double h, double psi) { return radius(dir_of(d_unit), h, psi); }

double cap_shadow_union_area(Vec3 i_unit, Vec3 o_unit, double h) {
  const Dir d_i = dir_of(i_unit), d_o = dir_of(o_unit);
  const double rs2 = std::max(0.0, 1 - h * h);
  // Excess of max(r_i, r_o)^2 over the disc, 1/2 ∮ dpsi, from psi0 = phi_i - pi.
  auto excess = [&](double psi) {
    const double r = std::max(radius(d_i, h, psi), radius(d_o, h, psi));
    return 0.5 * (r * r - rs2);
  };
  const double psi0 = d_i.phi - kPi;
  std::vector<double> cuts{psi0, psi0 + 2 * kPi};
  std::vector<double> kinks;
  add_kinks(d_i, h, kinks);
  add_kinks(d_o, h, kinks);
  if (kinks.empty()) return 0.0;  // both radii are the disc's
  for (double k : kinks) cuts.push_back(psi0 + std::fmod(std::fmod(k - psi0, 2 * kPi) + 2 * kPi, 2 * kPi));
  // Crossings r_i = r_o: sign changes of r_i - r_o on a grid, refined by the
  // Illinois method. (A pair missed inside one grid step only slows the adaptive rule.)
  constexpr int grid = 48;
  auto diff = [&](double psi) { return radius(d_i, h, psi) - radius(d_o, h, psi); };
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
  // Absolute tolerance 1e-10 of the area's scale (a 10-point estimate): the
  // area grows like 1/cos theta_d, up to ~1e3 at grazing angles.
  static const GaussLegendre g(10);
  double scale = 1;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    if (cuts[k + 1] - cuts[k] > 1e-15) scale += std::fabs(g.integrate(excess, cuts[k], cuts[k + 1]));
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    if (hi - lo <= 1e-15) continue;
    sum += integrate_adaptive(excess, lo, hi, 1e-10 * scale / cuts.size());
  }
  return sum;
}

double distant_masking_union(const GrainField& f, Vec3 i, Vec3 o, double h) {
  // exp(-rho' A) = (1 - tau0)^(A / pi)
  return std::exp(std::log1p(-f.tau0) * cap_shadow_union_area(to_unit_direction(f, i), to_unit_direction(f, o), h) / kPi);
}

}  // namespace mcref::micrograin
