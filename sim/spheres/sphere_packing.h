#pragma once
// Lambertian-sphere volumes (d'Eon 2021): opaque spheres of radius r and
// Lambertian albedo c filling a laterally periodic slab, or the homogeneous
// medium they tend to in the dilute limit. Parsed by sim/spheres/spheres_config.cpp.
//
// Frame: z up (the macro normal). Sphere centres lie in z in [-depth, 0]; the
// plane z = 0 is the plane of the highest centre (spheres protrude up to z = r).
// Laterally the packing is periodic with period `tile` (in radii).
// Lengths inside the simulation are in sphere radii (the BRDF of a half-space
// does not depend on the scale).
#include <cstdint>
#include <string>
#include <vector>

#include "models/core/rgb.h"
#include "models/core/vec.h"

namespace mcref {

class Rng;

enum class SpherePlacement {
  poisson,     // independent centres, overlaps allowed: f = 1 - exp(-n 4 pi r^3 / 3)
  rsa,         // random sequential addition of non-overlapping spheres: f = n 4 pi r^3 / 3
  volumetric,  // homogeneous medium, extinction n pi r^2, Lambert-sphere phase function (Eq. 1)
};
const char* placement_name(SpherePlacement p);

// Random sequential addition jams at f ~ 0.384 (3D); its approach is slow
// (t^-1/3), so we refuse volume fractions above this.
inline constexpr double kRsaMaxVolumeFraction = 0.36;

struct SpherePacking {
  bool configured = false;
  double radius = 1.0;        // r (only sets the units of the stored geometry)
  Rgb albedo{0.8};            // c per RGB channel, in [0, 1]
  double volume_fraction = 0.07;  // f
  SpherePlacement placement = SpherePlacement::poisson;
  double transmission_threshold = 1e-4;  // target transmission of the slab
  double depth_mfp = 0;       // slab depth in mean free paths 1/(n pi r^2); 0: from the threshold
  double tile = 100.0;        // lateral period, in radii (explicit packings)

  // Number density n, per r^3.
  double number_density() const;
  // Extinction n pi r^2, per r.
  double extinction() const { return number_density() * kPi; }
  // Depth actually used, in mean free paths (depth_mfp, or the estimate below).
  double depth_in_mfp() const;
  // Depth in radii.
  double depth() const { return depth_in_mfp() / extinction(); }
  // Expected sphere count per realization (explicit placements).
  double expected_count() const;
};

// The depth (mean free paths) at which a slab of albedo c with the
// Lambert-sphere phase function (g = -4/9) transmits less than `threshold`:
// T ~ A exp(-s0 depth), s0 the asymptotic decay rate of the diffuse radiance
// (models/lambert_sphere/decay_rate.h; 1 at low albedo, where the unscattered
// exp(-depth) dominates), A <= kTransmissionPrefactor (measured at normal
// incidence: 1.6-1.8 at c = 0.6-0.64, tests/sim/spheres). At c = 1: 4 / (3 (1 - g) threshold).
// (Diffusion's 1 / sqrt(3 (1 - c)(1 - g)) decay length with a prefactor 2 left
// 1.27 times the threshold at c = 0.64.)
inline constexpr double kTransmissionPrefactor = 4;
double transmission_depth_mfp(double c, double threshold);

// Free flights longer than this many tile periods make the walk wrap the
// periodic tile as many times per flight: the cost cliff of dilute packings.
inline constexpr double kMaxTilesPerFreeFlight = 100;

// One realization of the centres (radius units, r = 1), x, y in [0, tile),
// z in [-depth, 0], shifted so that the highest centre is at z = 0.
std::vector<Vec3> place_poisson(const SpherePacking& p, Rng& rng);
// RSA with a uniform grid, periodic in x, y and z (z over kRsaPadding radii more
// than the depth on both sides) and cut to [-depth, 0]: no denser layer at the
// faces; the count kept varies. Throws std::runtime_error if the attempt budget is
// exhausted before the target count (which can only happen near jamming).
inline constexpr double kRsaPadding = 8;  // radii: 4 diameters, past the RSA pair correlation
std::vector<Vec3> place_rsa(const SpherePacking& p, Rng& rng);
std::vector<Vec3> place_spheres(const SpherePacking& p, Rng& rng);

}  // namespace mcref
