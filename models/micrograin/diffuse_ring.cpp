#include "models/micrograin/diffuse_ring.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/microfacet/fresnel.h"
#include "models/micrograin/clipped_cosines.h"

namespace mcref::micrograin {

namespace {

constexpr int kMaxHalvings = 12;  // bounds the work: at most 2^12 parts per piece

// ∫_a^b g: the 24-point value `fine`, accepted when the 16-point rule agrees with
// it to tol (or to rounding); else each half with tol / 2.
template <class G>
double checked_piece(const G& g, double a, double b, double fine, double tol, int halvings) {
  static const GaussLegendre coarse_rule(16), fine_rule(24);
  const double diff = std::fabs(coarse_rule.integrate(g, a, b) - fine);
  if (halvings == 0 || diff <= tol || diff <= 1e-14 * std::fabs(fine)) return fine;
  const double m = 0.5 * (a + b);
  return checked_piece(g, a, m, fine_rule.integrate(g, a, m), 0.5 * tol, halvings - 1) +
         checked_piece(g, m, b, fine_rule.integrate(g, m, b), 0.5 * tol, halvings - 1);
}

// ∫_0^2pi g for a periodic g analytic on the real line: the trapezoid rule with
// n = 32, 64, ... points (each holding the last), accepted when it agrees with
// the last to rel_tol; its error falls exponentially with n.
template <class G>
double periodic_trapezoid(const G& g, double rel_tol) {
  constexpr int kMaxPoints = 1 << 12;
  double sum = 0;
  for (int j = 0; j < 16; ++j) sum += g(2 * kPi * j / 16);
  double last = sum * 2 * kPi / 16;
  for (int n = 32;; n *= 2) {
    for (int j = 1; j < n; j += 2) sum += g(2 * kPi * j / n);  // the new (odd) points
    const double value = sum * 2 * kPi / n;
    if (n == kMaxPoints || std::fabs(value - last) <= rel_tol * std::fabs(value)) return value;
    last = value;
  }
}

}  // namespace

double diffuse_ring_integral(const GrainField& f, Vec3 i, Vec3 o, double ior, double h, double st, double rel_tol) {
  const Sinusoid p_i{h * i.z, st * f.beta_x * i.x, st * f.beta_y * i.y}, p_o{h * o.z, st * f.beta_x * o.x, st * f.beta_y * o.y};
  const bool fresnel = ior > 1;
  // Isotropic grains without Fresnel: |M m'| is constant on the ring.
  if (!fresnel && f.beta_x == f.beta_y) return clipped_product_integral(p_i, p_o) / std::hypot(st * f.beta_x, h);
  const double sx = st * f.beta_x, sy = st * f.beta_y;
  auto integrand = [&](double a) {
    const double ca = std::cos(a), sa = std::sin(a);
    const double pi = p_i.A + p_i.B * ca + p_i.C * sa, po = p_o.A + p_o.B * ca + p_o.C * sa;
    if (pi <= 0 || po <= 0) return 0.0;
    const double len = std::sqrt(sx * sx * ca * ca + sy * sy * sa * sa + h * h);  // |M m'|
    double t = 1;
    if (fresnel) t = (1 - fresnel_dielectric(pi / len, ior)) * (1 - fresnel_dielectric(po / len, ior));
    return pi * po * t / len;
  };
  std::vector<double> zeros;
  add_sinusoid_zeros(p_i, zeros);
  add_sinusoid_zeros(p_o, zeros);
  if (zeros.empty()) return integrand(0) > 0 ? periodic_trapezoid(integrand, rel_tol) : 0.0;  // one sign each on the ring
  std::sort(zeros.begin(), zeros.end());
  // The pieces between consecutive zeros (the last one wrapping round), where
  // both sinusoids are positive, with their 24-point values (the ring's scale).
  static const GaussLegendre fine_rule(24);
  struct Piece {
    double a, b, fine;
  };
  std::vector<Piece> pieces;
  double scale = 0;
  for (std::size_t k = 0; k < zeros.size(); ++k) {
    const double a = zeros[k], b = k + 1 < zeros.size() ? zeros[k + 1] : zeros[0] + 2 * kPi;
    if (!(b > a) || integrand(0.5 * (a + b)) == 0) continue;  // one sinusoid is negative on the piece
    pieces.push_back({a, b, fine_rule.integrate(integrand, a, b)});
    scale += pieces.back().fine;
  }
  double ring = 0;
  for (const Piece& p : pieces)
    ring += checked_piece(integrand, p.a, p.b, p.fine, rel_tol * scale * (p.b - p.a) / (2 * kPi), kMaxHalvings);
  return ring;
}

}  // namespace mcref::micrograin
