// [geometry] kind = "slab": parsing and validation (issue #4).
#include "sim/config/experiment_parts.h"

namespace mcref {

void read_slab_geometry(TomlReader& g, Experiment& e) {
  g.fail("kind", "= \"slab\" is not implemented yet (issue #4)");
}

}  // namespace mcref
