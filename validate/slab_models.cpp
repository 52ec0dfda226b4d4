// Models of the slab family (to be filled in by its issue).
#include <stdexcept>

#include "validate/model_evaluation.h"

namespace mcref {

const ModelFamily& slab_models() {
  static const ModelFamily family{{}, [](const std::string& model, const Table&, const Experiment&) -> std::vector<double> {
                                    throw std::invalid_argument("no model " + model);
                                  }};
  return family;
}

}  // namespace mcref
