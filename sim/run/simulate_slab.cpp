// Microflake slabs (issue #4).
#include <stdexcept>

#include "sim/run/simulate_kinds.h"

namespace mcref {

std::vector<Table> simulate_slab(const Experiment& ex, Progress& progress) {
  throw std::logic_error("slab simulation is not implemented yet (issue #4)");
}

}  // namespace mcref
