#pragma once
// SpongeCake's approximation of multiple scattering (Wang et al. 2022, Sec. 5):
//   f_ms(wi, wo) = W1 f_ss'(wi, wo) + W2 f_lambert(wi, wo)
// f_ss' is the single-scattering BSDF (Eq. 8-16, layers Sec. 4.4) of the same
// stack with modified parameters alpha', gamma' (RGB), T', f0' (RGB) per layer;
// each layer keeps its flake type k and orientation omega_p (Figs. 5-6:
// "unmodified parameters") and its density rho. W1, W2 are scalars, as the
// paper lists them among the network's outputs (one each, not RGB).
// The full BSDF is f_ss + f_ms (the "three lobes" of Sec. 5).
//
// What the paper leaves open, and the choices here:
// - How the Lambertian lobe splits between reflection and transmission: Sec. 5
//   says only "a Lambertian lobe". LambertianSplit makes it a parameter:
//   f_lambert = reflection / pi when wi, wo are on the same side, transmission / pi
//   when on opposite sides. Default {1, 1}: one Lambertian lobe over the whole
//   sphere of wo (energy W2 reflected and W2 transmitted), the reading in which
//   "a Lambertian lobe" of a BSDF whose dataset holds both hemispheres (Figs. 9-10)
//   needs no further parameter. {1, 0}: a BRDF-only Lambertian lobe.
// - Output ranges: not stated. Here: W1, W2 >= 0, alpha' > 0, T' >= 0,
//   gamma', f0' in [0, 1] (the ranges of the inputs). Note that W1 and gamma'
//   enter only as the products W1 gamma'_c (F = gamma Schlick(f0), Eq. 11), so
//   (W1, gamma') is not identifiable beyond those products.
// Conventions as in single_scattering.h: BSDF values in 1/sr without cosine;
// wi, wo point away from the surface; light may come from either side.
#include <string>
#include <vector>

#include "models/core/rgb.h"
#include "models/sggx/flake_layer.h"

namespace mcref::sggx {

// Lambertian lobe per side: reflection / pi (same side), transmission / pi
// (opposite sides); its albedo from any wi is reflection (resp. transmission).
struct LambertianSplit {
  double reflection = 1;
  double transmission = 1;
};

// The modified parameters of one layer (alpha', T', gamma', f0').
struct ModifiedLayer {
  double alpha = 1;
  double thickness = 1;
  Rgb albedo{1, 1, 1};
  Rgb f0{1, 1, 1};
};

// The parameters of the two added lobes (the network's outputs, Sec. 5).
struct MultipleScatteringLobes {
  std::vector<ModifiedLayer> layers;  // one per layer of the stack, from the top
  double w1 = 0;                      // weight of the modified single-scattering lobe
  double w2 = 0;                      // weight of the Lambertian lobe
  LambertianSplit split;
};

// Throws std::invalid_argument naming the key, value and allowed range (and
// the layer count when it differs from the stack's).
void check_lobes(const MultipleScatteringLobes& lobes, std::size_t stack_layers);
// The modified stack: each original layer with alpha, T, gamma, f0 replaced
// (type, orientation and density kept).
std::vector<FlakeLayer> modified_stack(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes);
// f_lambert(wi, wo) without the weight W2; 0 at grazing (wi.z or wo.z = 0).
double lambertian_lobe(const LambertianSplit& split, Vec3 wi, Vec3 wo);
// f_ms for channel c: W1 f_ss'(wi, wo) + W2 f_lambert(wi, wo). Checks its input.
double multiple_scattering_bsdf(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes, int c,
                                Vec3 wi, Vec3 wo);
// All three channels.
Rgb multiple_scattering_bsdf_rgb(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes,
                                 Vec3 wi, Vec3 wo);

}  // namespace mcref::sggx
