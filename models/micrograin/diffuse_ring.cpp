#include "models/micrograin/diffuse_ring.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/microfacet/fresnel.h"
#include "models/micrograin/checked_gauss_legendre.h"
#include "models/micrograin/clipped_cosines.h"

namespace mcref::micrograin {

namespace {

constexpr int kMaxHalvings = 12;  // bounds the work: at most 2^12 parts per piece

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
  struct Piece {
    double a, b, fine;
  };
  std::vector<Piece> pieces;
  double scale = 0;
  for (std::size_t k = 0; k < zeros.size(); ++k) {
    const double a = zeros[k], b = k + 1 < zeros.size() ? zeros[k + 1] : zeros[0] + 2 * kPi;
    if (!(b > a) || integrand(0.5 * (a + b)) == 0) continue;  // one sinusoid is negative on the piece
    pieces.push_back({a, b, gauss_legendre_24(integrand, a, b)});
    scale += pieces.back().fine;
  }
  // Absolute tolerance: rel_tol of the ring, but not below the rounding of
  // P_i P_o / |M m'| (2^-50 of its unclipped bound), which a ring clipped to
  // slivers (e.g. near the equator, h -> 0) could otherwise never meet.
  const auto amplitude = [](const Sinusoid& p) { return std::fabs(p.A) + std::hypot(p.B, p.C); };
  const double unclipped = 2 * kPi * amplitude(p_i) * amplitude(p_o) / std::hypot(std::min(sx, sy), h);
  const double tol = std::max(rel_tol * scale, 0x1p-50 * unclipped);
  const auto rounding = [](double, double) { return 1e-14; };
  double ring = 0;
  for (const Piece& p : pieces) ring += checked_gauss_legendre(integrand, p.a, p.b, p.fine, tol, rounding, kMaxHalvings);
  return ring;
}

}  // namespace mcref::micrograin
