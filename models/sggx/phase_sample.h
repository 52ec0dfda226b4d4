#pragma once
// Result of sampling a phase function (pbrt-v4 style "optional sample").
#include "models/core/vec.h"

namespace mcref::sggx {

// Direction convention shared by every phase function of this family:
// wi points AWAY from the scattering point toward where the light came from
// (the reversed propagation direction of the arriving photon), wo points away
// from the scattering point along the new propagation direction. A photon
// travelling along d that scatters continues along wo, with wi = -d.
struct PhaseSample {
  Vec3 wo;             // sampled outgoing direction (unit)
  double pdf = 0;      // solid-angle density of wo = normalised phase function f_p(wi -> wo)
  double weight = 0;   // throughput multiplier: albedo-weighted phase / pdf
                       // (flake reflectance F(h) for flakes, the albedo for HG/isotropic)
  bool valid = false;  // false if no direction could be produced (weight 0)
};

}  // namespace mcref::sggx
