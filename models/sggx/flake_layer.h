#pragma once
// One SGGX flake layer as SpongeCake's Sec. 5 describes it (the network's
// inputs, and the dataset's per-layer parameters): flake type k (surface or
// fibre), roughness alpha, thickness T (and density rho), albedo gamma (RGB),
// Schlick f0 (RGB), orientation omega_p. flake_stack() gives the one-channel
// Layers the single-scattering model (single_scattering.h) evaluates.
#include <string>
#include <vector>

#include "models/core/rgb.h"
#include "models/sggx/layer.h"

namespace mcref::sggx {

enum class FlakeType { kSurface, kFiber };

struct FlakeLayer {
  FlakeType type = FlakeType::kSurface;
  double alpha = 1;          // SGGX roughness, > 0
  double thickness = 1;      // T >= 0 (finite)
  double density = 1;        // rho >= 0; the model depends on T rho only (Eq. 10)
  Rgb albedo{1, 1, 1};       // gamma in [0, 1] per channel
  Rgb f0{1, 1, 1};           // Schlick normal reflectance in [0, 1] per channel
  Vec3 orientation{0, 0, 1};  // omega_p, non-zero (normalised here)
};

// Throws std::invalid_argument "<what>: <key> = <value> is out of range
// (allowed: <range>)" unless ok.
void require_parameter(bool ok, const std::string& what, const std::string& key, double value,
                       const std::string& range);
// Throws std::invalid_argument naming `what` (e.g. "layer 1"), the key, its
// value and the allowed range when a parameter is out of range.
void check_flake_layer(const FlakeLayer& l, const std::string& what);
// Channel c (0, 1, 2) of the layer: an SGGX specular-flake Layer.
Layer flake_channel_layer(const FlakeLayer& l, int c);
// The stack (listed from the top) for channel c.
std::vector<Layer> flake_stack(const std::vector<FlakeLayer>& layers, int c);

}  // namespace mcref::sggx
