#pragma once
// The ring integral of the G_dist diffuse geometry in closed form (vNDF paper
// Eq. 1 and 7, issue #15 part 4): on a ring of unit-space normals at polar
// angle theta', |M m'| <d.m> = A + B cos a + C sin a (d = i, o), and for
// isotropic grains |M m'| is constant on the ring, so the ring integral of
// <i.m>+ <o.m>+ |M m'| is
//   (1 / |M m'|) ∫_0^2pi max(0, P_i(a)) max(0, P_o(a)) da,
// a trigonometric polynomial of degree 2 between the zeros of P_i and P_o,
// integrated exactly here (differences by half-angle formulas, no cancellation
// of the antiderivative's values).
#include <vector>

namespace mcref::micrograin {

// P(a) = A + B cos a + C sin a.
struct Sinusoid {
  double A, B, C;
};

// The zeros of p in [0, 2 pi) (none if p keeps one sign), appended to `cuts`.
void add_sinusoid_zeros(const Sinusoid& p, std::vector<double>& cuts);

// ∫_0^2pi max(0, p(a)) max(0, q(a)) da.
double clipped_product_integral(const Sinusoid& p, const Sinusoid& q);

}  // namespace mcref::micrograin
