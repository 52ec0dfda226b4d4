#pragma once
// Grain and base micro-BRDFs of micrograin transport (issue #3), parsed by
// sim/config/micrograin_materials.cpp from the experiment's [material] table.
namespace mcref {

struct MicrograinMaterials {
  bool configured = false;
};

}  // namespace mcref
