#pragma once
// Warps from the unit square to common domains (pbrt-v4 style).
#include "sim/core/rng.h"
#include "sim/core/small_angle.h"
#include "sim/core/vec.h"

namespace mcref {

// Uniform point on the unit disc (concentric map not needed: polar is exact).
inline void sample_uniform_disc(double u1, double u2, double& x, double& y) {
  const double r = std::sqrt(u1);
  const SinCos phi = sincos_turn(u2);  // phi = 2 pi u2
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

// Uniform direction on the unit sphere, pdf = 1/(4 pi).
inline Vec3 sample_uniform_sphere(double u1, double u2) {
  const double z = 1 - 2 * u1, r = std::sqrt(std::fmax(0.0, 1 - z * z));
  const SinCos phi = sincos_turn(u2);  // phi = 2 pi u2
  return {r * phi.cos, r * phi.sin, z};
}

}  // namespace mcref
