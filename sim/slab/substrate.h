#pragma once
// Substrate BSDFs under the bottom layer (SpongeCake Sec. 4.5): Lambertian,
// smooth conductor (exact Fresnel with complex IOR) and rough conductor (GGX,
// single-bounce microfacet BRDF with Smith height-uncorrelated G, sampled by
// visible normals, Heitz 2018). The substrate's normal is +z.
#include "models/core/rgb.h"
#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

struct SubstrateSample {
  Vec3 wo;
  Rgb weight;            // f cos / pdf
  bool specular = false; // a delta lobe (smooth conductor)
  bool valid = false;
};

// wi points up (toward where the light came from), wi.z > 0.
SubstrateSample sample_substrate(const SlabSubstrate& s, Vec3 wi, Rng& rng);
// The same from two uniforms in [0, 1) (the smooth conductor ignores them).
SubstrateSample sample_substrate(const SlabSubstrate& s, Vec3 wi, double u1, double u2);
// f(wi, wo) without the cosine (0 for the smooth conductor: a delta lobe).
Rgb eval_substrate(const SlabSubstrate& s, Vec3 wi, Vec3 wo);

}  // namespace mcref::volume
