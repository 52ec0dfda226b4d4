#pragma once
// The isotropic GGX microfacet pieces shared by the rough-conductor micro-BRDF
// of grains and bases (sim/micrograin/micro_brdf) and the rough-conductor slab
// substrate (sim/slab/substrate), in a local frame with the normal +z; and
// the per-channel Fresnel reflectance of a conductor eta + i kappa.
#include <cmath>

#include "models/core/rgb.h"
#include "models/core/vec.h"
#include "models/core/warp.h"
#include "models/microfacet/fresnel.h"

namespace mcref {

// Smith Lambda of GGX (infinite at grazing).
inline double ggx_lambda(double alpha, Vec3 w) {
  const double c2 = w.z * w.z, s2 = std::fmax(0.0, 1 - c2);
  if (!(c2 > 0)) return INFINITY;
  return 0.5 * (-1 + std::sqrt(1 + alpha * alpha * s2 / c2));
}

// GGX normal distribution D(m).
inline double ggx_d(double alpha, Vec3 m) {
  if (m.z <= 0) return 0;
  const double a2 = alpha * alpha, c2 = m.z * m.z, t = c2 * a2 + (1 - c2);
  return a2 / (kPi * t * t);
}

// Heitz 2018, "Sampling the GGX distribution of visible normals".
inline Vec3 sample_ggx_visible_normal(double alpha, Vec3 wi, double u1, double u2) {
  const Vec3 vh = normalize(Vec3{alpha * wi.x, alpha * wi.y, wi.z});
  const double lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0 ? Vec3{-vh.y, vh.x, 0} / std::sqrt(lensq) : Vec3{1, 0, 0};
  const Vec3 t2 = cross(vh, t1);
  double p1, p2;
  sample_uniform_disc(u1, u2, p1, p2);
  const double s = 0.5 * (1 + vh.z);
  p2 = (1 - s) * std::sqrt(std::fmax(0.0, 1 - p1 * p1)) + s * p2;
  const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::fmax(0.0, 1 - p1 * p1 - p2 * p2));
  return normalize(Vec3{alpha * nh.x, alpha * nh.y, std::fmax(1e-12, nh.z)});
}

// Unpolarised Fresnel reflectance per channel at incidence cosine c.
inline Rgb fresnel_conductor(double c, const Rgb& eta, const Rgb& kappa) {
  return {micrograin::fresnel_conductor(c, eta.r, kappa.r), micrograin::fresnel_conductor(c, eta.g, kappa.g),
          micrograin::fresnel_conductor(c, eta.b, kappa.b)};
}

}  // namespace mcref
