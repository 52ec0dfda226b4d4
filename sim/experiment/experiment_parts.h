#pragma once
// The per-kind parts of experiment parsing, one file per geometry kind.
// Each reads its [geometry] keys (kind already read) and its materials.
#include <toml++/toml.h>

#include "sim/experiment/experiment.h"
#include "sim/experiment/toml_reader.h"

namespace mcref {

void read_micrograin_geometry(TomlReader& geometry, Experiment& e);
// After the measures: refuses directions whose rays would wrap the tile too often.
void check_micrograin_directions(const Experiment& e);
void read_slab_geometry(TomlReader& geometry, Experiment& e);
void read_spheres_geometry(TomlReader& geometry, Experiment& e);
// Optional [material] table of micrograin transport (issue #3); `table` may be null.
void read_micrograin_materials(const toml::table* table, Experiment& e);

}  // namespace mcref
