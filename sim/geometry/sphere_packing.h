#pragma once
// Lambertian-sphere volumes (d'Eon 2021): opaque spheres filling a laterally
// periodic half-space. Filled in by issue #5; parsed by sim/config/spheres_config.cpp.
#include <string>
#include <vector>

namespace mcref {

struct SpherePacking {
  bool configured = false;
};

}  // namespace mcref
