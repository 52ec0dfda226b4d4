#pragma once
// Micro-BRDFs of micrograin transport (issue #3): what a grain or the base
// does with the light that reaches it. Every model is energy-consistent
// (reflected energy <= incident, per RGB channel) and reciprocal, and is used
// by sampling only: sample() draws an outgoing direction with a weight
// f cos / pdf (RGB) so the path tracer never needs to evaluate f.
//
//   black             absorbs everything
//   lambertian        albedo K_d / pi
//   conductor         smooth mirror, exact Fresnel of eta + i kappa per channel
//   rough_conductor   GGX (alpha), visible-normal sampling (Heitz 2018),
//                     height-correlated Smith G2 = 1 / (1 + Lambda_i + Lambda_o),
//                     exact conductor Fresnel (single scattering: loses energy)
//   diffuse_specular  smooth dielectric interface (index ior) over a Lambertian
//                     body (albedo K_d): the Fresnel-weighted mirror lobe, and
//                     the refracted part scattered diffusely inside, bouncing
//                     between body and interface (Fresnel, total internal
//                     reflection) until it leaves, refracted (simulated exactly)
#include <string>

#include "models/core/rgb.h"
#include "models/core/rng.h"
#include "models/core/vec.h"

namespace mcref {

struct MicroBrdf {
  enum class Type { Black, Lambertian, Conductor, RoughConductor, DiffuseSpecular };
  Type type = Type::Lambertian;
  Rgb albedo{1.0};           // lambertian, diffuse_specular (body)
  Rgb eta{1.5}, kappa{0.0};  // conductors: complex index per channel
  double ior = 1.5;          // diffuse_specular: index of the dielectric interface
  double alpha = 0.3;        // rough_conductor: GGX roughness
  std::string name() const;  // the config's type string
};

struct MicroBrdfSample {
  Vec3 wo;             // world direction, pointing away from the surface; not
                       // unit length (lambertian: see sample_cosine_about)
  Rgb weight;          // f cos / pdf
  bool delta = false;  // an exact mirror direction
  bool absorbed = false;
};

// wi: world direction toward where the light comes from (wi . n > 0), of any
// length; n: unit normal.
MicroBrdfSample sample_micro_brdf(const MicroBrdf& b, Vec3 wi, Vec3 n, Rng& rng);

// Reflectance of the micro-BRDF for light from wi (energy that is reflected),
// exact where closed (black, lambertian, conductor); diffuse_specular and
// rough_conductor by the same sampling (`samples` draws). For tests.
Rgb micro_brdf_albedo(const MicroBrdf& b, double cos_theta_i, Rng& rng, int samples = 100000);

}  // namespace mcref
