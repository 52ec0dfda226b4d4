#pragma once
// Random walks of one path through a Lambertian-sphere volume, both forms:
//   packing_path:    explicit spheres (SphereField), Lambertian reflection on
//                    the sphere surface with probability c;
//   volumetric_path: the homogeneous half-space they tend to in the dilute
//                    limit (extinction n pi r^2 = 1 per mean free path, albedo
//                    c, phase function Eq. 1 sampled exactly by Eq. 5).
// Both carry RGB throughput, count scattering orders, end with unbiased Russian
// roulette (survival probability = max channel of the throughput, so the
// surviving weight's max channel is 1), and tally escaping light into a
// BrdfAccumulator (order-1 class 0 = "sphere") and the energy leaving through
// the bottom of the slab into `transmitted`.
#include "models/core/rgb.h"
#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/tally/brdf_tally.h"

namespace mcref {

class SphereField;

struct WalkSettings {
  Rgb albedo{0.8};
  int max_order = 0;  // 0: unlimited
  double depth_mfp = 100;  // volumetric: slab depth in mean free paths
};

// wi: incident direction (toward the light, wi.z > 0).
void packing_path(const SphereField& field, const WalkSettings& s, Vec3 wi, Rng& rng, BrdfAccumulator& acc,
                  Rgb& transmitted);
void volumetric_path(const WalkSettings& s, Vec3 wi, Rng& rng, BrdfAccumulator& acc, Rgb& transmitted);

// Russian roulette on the throughput; false if the path is terminated.
bool russian_roulette(Rgb& weight, Rng& rng);

}  // namespace mcref
