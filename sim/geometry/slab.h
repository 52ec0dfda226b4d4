#pragma once
// Microflake slabs (SpongeCake): a stack of plane-parallel layers of
// scattering media over an optional substrate, infinite laterally.
// Filled in by the slab engine (issue #4); parsed by sim/config/slab_config.cpp.
#include <string>
#include <vector>

namespace mcref {

struct SlabGeometry {
  bool configured = false;
};

}  // namespace mcref
