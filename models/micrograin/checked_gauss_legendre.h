#pragma once
// A checked Gauss-Legendre rule for the G_dist diffuse geometry's integrals
// (diffuse_ring.h, micrograin_bsdf.cpp): on [a, b] the 24-point value is
// accepted where a 16-point rule agrees with it to tol (absolute) or to the
// integrand's own rounding (`floor(a, b)`, relative); else each half is
// checked with tol / 2, at most `halvings` times. For a piece on which the
// integrand is analytic the 16-point rule's error bounds the 24-point one's
// by far, so the result is accurate to well below tol.
#include "models/core/quadrature.h"

namespace mcref::micrograin {

template <class G>
double gauss_legendre_24(const G& g, double a, double b) {
  static const GaussLegendre rule(24);
  return rule.integrate(g, a, b);
}

// `fine`: the 24-point value on [a, b] (the caller's scale).
template <class G, class Floor>
double checked_gauss_legendre(const G& g, double a, double b, double fine, double tol, const Floor& floor, int halvings) {
  static const GaussLegendre check_rule(16);
  const double diff = std::fabs(check_rule.integrate(g, a, b) - fine);
  if (halvings == 0 || diff <= tol || diff <= floor(a, b) * std::fabs(fine)) return fine;
  const double m = 0.5 * (a + b);
  return checked_gauss_legendre(g, a, m, gauss_legendre_24(g, a, m), 0.5 * tol, floor, halvings - 1) +
         checked_gauss_legendre(g, m, b, gauss_legendre_24(g, m, b), 0.5 * tol, floor, halvings - 1);
}

}  // namespace mcref::micrograin
