#pragma once
// SGGX microflake distribution (Heitz, Dupuy, Crassin, Dachsbacher 2015,
// "The SGGX microflake distribution"; SpongeCake Eq. 3 and 7).
//
// Conventions: all directions are unit vectors in the world (shading) frame,
// z = macro normal. D is symmetric, D(m) = D(-m). D is NOT a probability
// density on the sphere: its normalisation is the projected area
//   sigma(w) = \int <w.m>^+ D(m) dm = sqrt(w^T S w)        (SpongeCake Eq. 3)
// (e.g. S = I gives D = 1/pi and \int D dm = 4). The visible normal density
//   D_w(m) = <w.m>^+ D(m) / sigma(w)
// integrates to 1 over the sphere.
#include <algorithm>
#include <cmath>

#include "models/core/frame.h"
#include "models/core/vec.h"
#include "models/core/warp.h"
#include "models/sggx/mat3.h"

namespace mcref::sggx {

// An SGGX matrix with its precomputed inverse, Cholesky factor and sqrt(det).
struct Sggx {
  Mat3 S;            // symmetric positive definite
  Mat3 S_inv;        // S^-1
  Mat3 L;            // S = L L^T (lower triangular); drives the vNDF sampler
  double sqrt_det;   // sqrt(det S)
};

// Any symmetric positive definite S; throws std::invalid_argument otherwise.
Sggx from_matrix(const Mat3& S);
// S = R diag(a^2, a^2, 1) R^T with R z = wp (flakes' normals around +-wp):
// equals a^2 I + (1 - a^2) wp wp^T. alpha > 0; wp need not be normalised.
Sggx surface_like(double alpha, Vec3 wp);
// S = R diag(1, 1, a^2) R^T with R z = wp (fibres along wp; normals near the
// plane orthogonal to wp): equals I + (a^2 - 1) wp wp^T.
Sggx fiber_like(double alpha, Vec3 wp);

// D(m) = 1 / (pi sqrt(det S) (m^T S^-1 m)^2)   (Heitz 2015 Eq. 9; SpongeCake Eq. 7
// in the general form; m need not be normalised: D is evaluated at m/|m|).
// (From S^-1 and sqrt(det S) alone: the wave walk's lanes hold no Sggx.)
inline double ndf(const Mat3& S_inv, double sqrt_det, Vec3 m) {
  const double q = quadratic_form(S_inv, m) / dot(m, m);
  return 1.0 / (kPi * sqrt_det * q * q);
}
inline double ndf(const Sggx& s, Vec3 m) { return ndf(s.S_inv, s.sqrt_det, m); }
// SpongeCake Eq. 7 exactly as printed, 1 / (pi alpha q^2), q = m^T S^-1 m.
// Equals ndf() for fibre-like S (sqrt det S = alpha) but is alpha * ndf() for
// surface-like S (sqrt det S = alpha^2). For reports only.
double ndf_eq7_as_printed(const Sggx& s, double alpha, Vec3 m);
// sigma(w) = sqrt(w^T S w) = \int <w.m>^+ D(m) dm  (Eq. 3 and 7).
// (std::max, not std::fmax: the same for any q, NaN included, and it vectorises.)
inline double projected_area(const Sggx& s, Vec3 w) { return std::sqrt(std::max(0.0, quadratic_form(s.S, w))); }
// Visible normal density <w.m>^+ D(m) / sigma(w) w.r.t. solid angle of m.
double visible_ndf(const Sggx& s, Vec3 w, Vec3 m);
// Visible normal for direction w (unit), distributed as visible_ndf(s, w, .):
// the flakes are the normals of the ellipsoid {x : x^T S x <= 1}; with
// S = L L^T, x = L^-T u maps the unit ball onto it, normals map as n ~ L u and
// the view direction as w_u ~ L^T w. A uniform point in the projected disc of
// the unit sphere along w_u (a cosine-distributed u around w_u) is a uniform
// point in the ellipsoid's projected area, i.e. an exact vNDF sample (the same
// construction as Heitz 2015 Sec. 5 / sample_VNDF, written with Cholesky).
// u1, u2 uniform in [0, 1). Always returns m with dot(w, m) >= 0.
// (Inline, branch-free: the wave walk vectorises it.)
inline Vec3 sample_visible_normal(const Sggx& s, Vec3 w, double u1, double u2) {
  const Vec3 wu = normalize(transpose(s.L) * w);                        // view direction in ball space
  const Vec3 u = Frame(wu).to_world(sample_cosine_hemisphere(u1, u2));  // visible point
  const Vec3 m = normalize(s.L * u);                                    // ellipsoid normal there
  return m * (dot(m, w) < 0 ? -1.0 : 1.0);  // rounding at the silhouette (a select of numbers, not of vectors)
}

}  // namespace mcref::sggx
