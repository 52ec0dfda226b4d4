#include "sim/slab/substrate.h"

#include <cmath>

#include "models/core/warp.h"
#include "models/microfacet/ggx.h"

namespace mcref::volume {

SubstrateSample sample_substrate(const SlabSubstrate& s, Vec3 wi, Rng& rng) {
  using K = SlabSubstrate::Kind;
  if (s.kind != K::kLambertian && s.kind != K::kRoughConductor) return sample_substrate(s, wi, 0.0, 0.0);  // draws nothing
  const double u1 = rng.uniform(), u2 = rng.uniform();
  return sample_substrate(s, wi, u1, u2);
}

SubstrateSample sample_substrate(const SlabSubstrate& s, Vec3 wi, double u1, double u2) {
  SubstrateSample r;
  switch (s.kind) {
    case SlabSubstrate::Kind::kNone: return r;
    case SlabSubstrate::Kind::kLambertian:
      r.wo = sample_cosine_hemisphere(u1, u2);
      r.weight = s.albedo;
      r.valid = true;
      return r;
    case SlabSubstrate::Kind::kConductor:
      r.wo = {-wi.x, -wi.y, wi.z};
      r.weight = fresnel_conductor(wi.z, s.eta, s.k);
      r.specular = true;
      r.valid = true;
      return r;
    case SlabSubstrate::Kind::kRoughConductor: break;
  }
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
