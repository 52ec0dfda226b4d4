#pragma once
// Microflake slabs (SpongeCake, Wang et al. 2022): a stack of plane-parallel
// layers of scattering media over an optional substrate, infinite laterally.
// Parsed by sim/slab/slab_config.cpp; transported by the rest of sim/slab/.
//
// Geometry: the top face of the stack is the plane z = 0, layers are listed
// from the top down, layer k occupies depths [d_k, d_k + T_k] below it
// (z = -depth). Light arrives from above (directions point away from the
// surface, z = macro normal).
#include <memory>
#include <string>
#include <vector>

#include "models/core/rgb.h"
#include "models/core/vec.h"

namespace mcref {

enum class SlabPhase { kSggxSurface, kSggxFiber, kHenyeyGreenstein, kIsotropic, kLambertSphere };

// Relative density through a layer's depth: rho(s) = density * profile(s),
// s in [0, 1] from the top of the layer.
struct DensityProfile {
  enum class Kind { kConstant, kLinear, kTable };
  Kind kind = Kind::kConstant;
  double top = 1, bottom = 1;   // linear: multipliers at s = 0 and s = 1
  std::vector<double> table;    // table: multipliers at equally spaced s (>= 2), piecewise linear
  double at(double s) const;    // the multiplier at relative depth s
  double mean() const;          // integral over s in [0, 1]
  double max() const;
};

struct SlabLayer {
  SlabPhase phase = SlabPhase::kIsotropic;
  double thickness = 1;         // T
  double density = 1;           // rho (reference density, times the profile)
  DensityProfile profile;
  double alpha = 1;             // SGGX roughness
  Vec3 orientation{0, 0, 1};    // SGGX omega_p (unit): surface normal axis or fibre axis
  double g = 0;                 // Henyey-Greenstein asymmetry
  Rgb albedo{1, 1, 1};          // single-scattering albedo gamma (flakes: F = gamma Schlick(f0))
  Rgb f0{1, 1, 1};              // Schlick normal reflectance of the flakes
  // The density read from geometry.density_vdb (sim/slab/density_vdb.h), else
  // null: voxel (i, j, k) at (i * N + j) * (depth_voxels + 1) + k, i, j in [0, N)
  // (N = lateral_voxels), k = 0 on the layer's bottom face. density is then its
  // mean over the layer and profile constant.
  std::shared_ptr<const std::vector<float>> voxels;
  bool varies_laterally = false;  // the voxels differ across some voxel plane
  bool is_sggx() const { return phase == SlabPhase::kSggxSurface || phase == SlabPhase::kSggxFiber; }
  // Optical thickness T rho mean(profile) (along the normal, sigma = 1 units).
  double optical_thickness() const { return thickness * density * profile.mean(); }
  // True if the medium is symmetric about the z axis (azimuth can be folded).
  bool azimuthally_symmetric() const;
};

struct SlabSubstrate {
  enum class Kind { kNone, kLambertian, kConductor, kRoughConductor };
  Kind kind = Kind::kNone;
  Rgb albedo{1, 1, 1};          // lambertian
  Rgb eta{0.2, 0.92, 1.1};      // conductors: complex IOR eta + i k (per channel)
  Rgb k{3.9, 2.45, 2.14};
  double alpha = 0.3;           // rough conductor: GGX roughness
};

// How the slab walk tallies the light that leaves (sim/slab/walk.h).
enum class SlabEstimator { kAnalog, kNextEvent, kNextEventMis };

// Free-flight backend: exact per-layer exponential sampling of homogeneous
// layers, or delta tracking through OpenVDB density grids (any profile).
struct SlabGrid {
  bool openvdb = false;
  double tile = 1.0;            // lateral period of the density tile (same units as T)
  int lateral_voxels = 4;       // voxels per tile side
  int depth_voxels = 32;        // voxel planes per layer in depth (node-centred)
  std::string density_vdb;      // the densities' file (as given), or empty
};

struct SlabGeometry {
  bool configured = false;
  std::vector<SlabLayer> layers;  // top to bottom
  SlabSubstrate substrate;
  bool delta_transmission = true;  // record the unscattered transmission (Sec. 4.5)
  bool wave_walk = false;          // the data-parallel walk (sim/slab/wave_walk.h)
  SlabEstimator estimator = SlabEstimator::kAnalog;  // of the escaping light (sim/slab/walk.h)
  SlabGrid grid;
  double total_thickness() const;
  // Every layer's albedo is 1 and its flake Fresnel is 1, substrate none or a
  // white Lambertian one: no energy is absorbed (reflectance + transmittance,
  // delta lobe included, = 1).
  bool conservative() const;
};

}  // namespace mcref
