#pragma once
// Warps from the unit square to common domains (pbrt-v4 style).
#include <algorithm>

#include "models/core/rng.h"
#include "models/core/small_angle.h"
#include "models/core/vec.h"

namespace mcref {

// Uniform point on the unit disc (concentric map not needed: polar is exact).
inline void sample_uniform_disc(double u1, double u2, double& x, double& y) {
  const double r = std::sqrt(u1);
  const SinCos phi = sincos_turn_unit(u2);  // phi = 2 pi u2
  x = r * phi.cos;
  y = r * phi.sin;
}

// Cosine-weighted direction on the upper hemisphere, pdf = cos(theta)/pi.
inline Vec3 sample_cosine_hemisphere(double u1, double u2) {
  double x, y;
  sample_uniform_disc(u1, u2, x, y);
  return {x, y, std::sqrt(1.0 - u1)};  // x^2 + y^2 = u1
}

// The same density by Malley's method with the disc point drawn by rejection
// from the square (acceptance pi/4, 2.55 uniforms on average): exact, and
// without sin/cos, so cheaper per sample inside the micrograin walk.
inline Vec3 sample_cosine_hemisphere(Rng& rng) {
  double x, y, r2;
  do {
    x = 2 * rng.uniform() - 1;
    y = 2 * rng.uniform() - 1;
    r2 = x * x + y * y;
  } while (r2 >= 1);
  return {x, y, std::sqrt(1 - r2)};
}

// Uniform direction on the unit sphere by Marsaglia's method from a point of
// the disc drawn by rejection (exact, without sin/cos).
inline Vec3 sample_uniform_sphere(Rng& rng) {
  const Vec3 p = sample_cosine_hemisphere(rng);  // (x, y, sqrt(1 - r^2))
  const double s = 2 * p.z;
  return {p.x * s, p.y * s, 2 * p.z * p.z - 1};  // 1 - 2 r^2
}

// A cosine-distributed direction about the unit normal n, unnormalised:
// n + (a uniform point of the unit sphere), of length 2 cos(theta) in (0, 2].
// Exact: that point is uniform on the sphere of centre n through the origin,
// and seen from the origin such a sphere's area has density 4 cos(theta) per
// steradian. Needs no frame around n and no division. (A length below 1e-15,
// probability 2.5e-31, is drawn again, so the direction survives a float.)
inline Vec3 sample_cosine_about(Vec3 n, Rng& rng) {
  for (;;) {
    const Vec3 v = n + sample_uniform_sphere(rng);
    if (dot(v, v) >= 1e-30) return v;
  }
}

// Uniform direction on the unit sphere, pdf = 1/(4 pi).
inline Vec3 sample_uniform_sphere(double u1, double u2) {
  const double z = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - z * z));  // (max: vectorises)
  const SinCos phi = sincos_turn_unit(u2);  // phi = 2 pi u2
  return {r * phi.cos, r * phi.sin, z};
}

}  // namespace mcref
