#include "sim/volume/substrate.h"

#include <cmath>
#include <complex>

#include "sim/core/warp.h"

namespace mcref::volume {

double fresnel_conductor(double cos_theta, double eta, double k) {
  using C = std::complex<double>;
  const double ci = std::fmin(1.0, std::fabs(cos_theta));
  const C n(eta, k);
  const C sin2_t = (1 - ci * ci) / (n * n);
  const C ct = std::sqrt(C(1) - sin2_t);
  const C r_par = (n * ci - ct) / (n * ci + ct);
  const C r_perp = (ci - n * ct) / (ci + n * ct);
  return 0.5 * (std::norm(r_par) + std::norm(r_perp));
}

Rgb fresnel_conductor(double c, const Rgb& eta, const Rgb& k) {
  return {fresnel_conductor(c, eta.r, k.r), fresnel_conductor(c, eta.g, k.g), fresnel_conductor(c, eta.b, k.b)};
}

namespace {

double ggx_lambda(double alpha, Vec3 w) {
  const double c2 = w.z * w.z, s2 = std::fmax(0.0, 1 - c2);
  if (!(c2 > 0)) return INFINITY;
  return 0.5 * (-1 + std::sqrt(1 + alpha * alpha * s2 / c2));
}

double ggx_d(double alpha, Vec3 m) {
  if (m.z <= 0) return 0;
  const double a2 = alpha * alpha, c2 = m.z * m.z, t = c2 * a2 + (1 - c2);
  return a2 / (kPi * t * t);
}

// Heitz 2018, "Sampling the GGX distribution of visible normals" (isotropic alpha).
Vec3 sample_ggx_visible_normal(double alpha, Vec3 wi, double u1, double u2) {
  const Vec3 vh = normalize(Vec3{alpha * wi.x, alpha * wi.y, wi.z});
  const double lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 T1 = lensq > 0 ? Vec3{-vh.y, vh.x, 0} / std::sqrt(lensq) : Vec3{1, 0, 0};
  const Vec3 T2 = cross(vh, T1);
  double t1, t2;
  sample_uniform_disc(u1, u2, t1, t2);
  const double s = 0.5 * (1 + vh.z);
  t2 = (1 - s) * std::sqrt(std::fmax(0.0, 1 - t1 * t1)) + s * t2;
  const Vec3 nh = T1 * t1 + T2 * t2 + vh * std::sqrt(std::fmax(0.0, 1 - t1 * t1 - t2 * t2));
  return normalize(Vec3{alpha * nh.x, alpha * nh.y, std::fmax(1e-9, nh.z)});
}

}  // namespace

SubstrateSample sample_substrate(const SlabSubstrate& s, Vec3 wi, Rng& rng) {
  SubstrateSample r;
  switch (s.kind) {
    case SlabSubstrate::Kind::kNone: return r;
    case SlabSubstrate::Kind::kLambertian: {
      const double u1 = rng.uniform(), u2 = rng.uniform();
      r.wo = sample_cosine_hemisphere(u1, u2);
      r.weight = s.albedo;
      r.valid = true;
      return r;
    }
    case SlabSubstrate::Kind::kConductor:
      r.wo = {-wi.x, -wi.y, wi.z};
      r.weight = fresnel_conductor(wi.z, s.eta, s.k);
      r.specular = true;
      r.valid = true;
      return r;
    case SlabSubstrate::Kind::kRoughConductor: break;
  }
  const double u1 = rng.uniform(), u2 = rng.uniform();
  const Vec3 m = sample_ggx_visible_normal(s.alpha, wi, u1, u2);
  const double c = dot(wi, m);
  r.wo = m * (2 * c) - wi;
  if (!(r.wo.z > 0) || !(c > 0)) return r;  // leaves below the surface: absorbed (single-bounce model)
  // weight = F G2 / G1(wi) with height-uncorrelated G2 = G1(wi) G1(wo).
  r.weight = fresnel_conductor(c, s.eta, s.k) * (1 / (1 + ggx_lambda(s.alpha, r.wo)));
  r.valid = true;
  return r;
}

Rgb eval_substrate(const SlabSubstrate& s, Vec3 wi, Vec3 wo) {
  if (!(wi.z > 0) || !(wo.z > 0)) return {};
  switch (s.kind) {
    case SlabSubstrate::Kind::kLambertian: return s.albedo * (1 / kPi);
    case SlabSubstrate::Kind::kRoughConductor: {
      const Vec3 h = normalize(wi + wo);
      const double g = 1 / ((1 + ggx_lambda(s.alpha, wi)) * (1 + ggx_lambda(s.alpha, wo)));
      return fresnel_conductor(dot(wi, h), s.eta, s.k) * (ggx_d(s.alpha, h) * g / (4 * wi.z * wo.z));
    }
    default: return {};
  }
}

}  // namespace mcref::volume
