#pragma once
// The phase functions of slab layers behind one small interface: SGGX
// specular two-sided flakes (SpongeCake Eq. 4-5, Heitz 2015 visible-normal
// sampling), Henyey-Greenstein, isotropic, and the Lambert-sphere phase
// function (d'Eon 2021 Eq. 1/5).
//
// Directions: wi points toward where the light came from (the reversed
// propagation direction), wo along the new propagation direction.
#include <memory>

#include "models/core/rgb.h"
#include "models/core/rng.h"
#include "models/core/vec.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/slab/slab_geometry.h"

namespace mcref::volume {

struct ScatterSample {
  Vec3 wo;
  Rgb weight;          // albedo-weighted phase / pdf (RGB)
  bool valid = false;
};

class PhaseFunction {
 public:
  virtual ~PhaseFunction() = default;
  // Projected area sigma(w): the extinction along w is rho sigma(w) (Eq. 3);
  // 1 for ordinary (non-flake) media.
  virtual double sigma(Vec3 w) const { return 1.0; }
  // An upper bound of sigma over all directions (delta-tracking majorants).
  virtual double max_sigma() const { return 1.0; }
  // Normalised f_p(wi -> wo), \int f_p dwo = 1 (no albedo).
  virtual double eval(Vec3 wi, Vec3 wo) const = 0;
  // wo ~ f_p(wi -> .), weight = albedo (or flake reflectance F(m)); its pdf is eval(wi, wo).
  virtual ScatterSample sample(Vec3 wi, Rng& rng) const = 0;
  // The weight sample() gives wo: the albedo (flakes: gamma Schlick(f0, |wi.h|), Eq. 5).
  virtual Rgb albedo(Vec3 wi, Vec3 wo) const = 0;
};

std::unique_ptr<PhaseFunction> make_phase(const SlabLayer& layer);

// One event of specular two-sided SGGX flakes with matrix s: a visible normal
// m of wi (Heitz 2015), wo = wi reflected about m, weight = albedo Schlick(f0, |wi.m|).
// The layer phase function uses it with the layer's S; the OpenVDB path with S
// read from the grids at the scattering point.
ScatterSample sample_sggx_flakes(const sggx::Sggx& s, const Rgb& albedo, const Rgb& f0, Vec3 wi, Rng& rng);

}  // namespace mcref::volume
