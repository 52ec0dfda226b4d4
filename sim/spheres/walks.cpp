#include "sim/spheres/walks.h"

#include <cmath>

#include "models/core/frame.h"
#include "models/core/warp.h"
#include "models/lambert_sphere/phase_sampling.h"
#include "sim/spheres/sphere_field.h"

namespace mcref {

bool russian_roulette(Rgb& weight, Rng& rng) {
  const double q = std::fmin(1.0, weight.max());
  if (q >= 1.0) return true;
  if (q <= 0.0 || rng.uniform() >= q) return false;
  weight = weight / q;
  return true;
}

void packing_path(const SphereField& field, const WalkSettings& s, Vec3 wi, Rng& rng, BrdfAccumulator& acc,
                  Rgb& transmitted) {
  Vec3 o{rng.uniform() * field.tile(), rng.uniform() * field.tile(), field.top()};
  Vec3 d = -wi;
  Rgb weight(1.0);
  std::uint32_t on = SphereField::kNoSphere;
  for (int order = 0;; ++order) {
    const SphereHit h = field.trace(o, d, on);
    if (h.kind == SphereHit::Kind::Escape) {
      if (order > 0) acc.add(d, order, 0, weight, false);
      return;
    }
    if (h.kind == SphereHit::Kind::Transmit) {
      transmitted = transmitted + weight;
      return;
    }
    if (s.max_order > 0 && order + 1 > s.max_order) return;
    // Lambertian reflection (albedo c): cosine-weighted about the outward normal.
    weight = weight * s.albedo;
    if (!russian_roulette(weight, rng)) return;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    d = Frame(h.normal).to_world(sample_cosine_hemisphere(u1, u2));
    o = h.position;
    on = h.sphere;
  }
}

void volumetric_path(const WalkSettings& s, Vec3 wi, Rng& rng, BrdfAccumulator& acc, Rgb& transmitted) {
  // Laterally infinite and homogeneous: only the depth matters (z in [-depth, 0]).
  double z = 0;
  Vec3 d = -wi;
  Rgb weight(1.0);
  for (int order = 0;; ++order) {
    const double t = -std::log1p(-rng.uniform());  // free flight, extinction 1
    z += d.z * t;
    if (z >= 0) {
      if (order > 0) acc.add(d, order, 0, weight, false);
      return;
    }
    if (z <= -s.depth_mfp) {
      transmitted = transmitted + weight;
      return;
    }
    if (s.max_order > 0 && order + 1 > s.max_order) return;
    weight = weight * s.albedo;
    if (!russian_roulette(weight, rng)) return;
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
    const double mu = lambert_sphere::sample_phase_cosine_exact(u1, u2, u3);  // Eq. 5
    d = lambert_sphere::scattered_direction(d, mu, u4);
  }
}

}  // namespace mcref
