// Lambertian-sphere volumes (issue #5).
#include <stdexcept>

#include "sim/run/simulate_kinds.h"

namespace mcref {

std::vector<Table> simulate_spheres(const Experiment& ex, Progress& progress) {
  throw std::logic_error("sphere simulation is not implemented yet (issue #5)");
}

}  // namespace mcref
