// [material] of micrograin transport: grain and base micro-BRDFs (issue #3).
#include "sim/config/experiment_parts.h"

namespace mcref {

void read_micrograin_materials(const toml::table* table, Experiment& e) {
  if (table) throw ConfigError(e.file, "material", "micrograin transport is not implemented yet (issue #3)");
}

}  // namespace mcref
