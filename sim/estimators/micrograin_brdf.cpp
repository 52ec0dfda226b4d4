// brdf on micrograin fields: light transport with grain and base micro-BRDFs (issue #3).
#include <stdexcept>

#include "sim/config/config_error.h"
#include "sim/estimators/estimator.h"

namespace mcref {

Estimator micrograin_brdf_estimator() {
  Estimator e;
  e.make_tables = [](const Measure&, const Experiment& ex) -> std::vector<Table> {
    throw ConfigError(ex.file, "measure.quantity", "\"brdf\" on micrograin fields is not implemented yet (issue #3)");
  };
  e.add_batch = [](const MicrograinField&, const Experiment&, const Measure&, const StreamKey&, std::vector<Table>&) {};
  return e;
}

}  // namespace mcref
