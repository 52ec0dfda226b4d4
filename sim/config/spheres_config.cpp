// [geometry] kind = "spheres": parsing and validation (issue #5).
#include "sim/config/experiment_parts.h"

namespace mcref {

void read_spheres_geometry(TomlReader& g, Experiment& e) {
  g.fail("kind", "= \"spheres\" is not implemented yet (issue #5)");
}

}  // namespace mcref
