#pragma once
// Grain and base micro-BRDFs of micrograin transport (issue #3), parsed by
// sim/micrograin/micrograin_materials.cpp from the experiment's [material] table:
//   [material.grain]  type = "lambertian" | "conductor" | "rough_conductor" | "diffuse_specular" | "black"
//   [material.base]   the same types
// with albedo (lambertian, diffuse_specular), eta + kappa or preset = "gold" /
// "copper" (conductors), ior (diffuse_specular), alpha (rough_conductor).
#include "sim/micrograin/micro_brdf.h"

namespace mcref {

struct MicrograinMaterials {
  bool configured = false;
  MicroBrdf grain;
  MicroBrdf base;
};

}  // namespace mcref
