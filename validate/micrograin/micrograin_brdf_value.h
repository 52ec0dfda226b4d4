#pragma once
// f(i, o) of an analytic micrograin_brdf model (sr^-1, without the cosine),
// all three channels: the integrand whose cell averages the model family
// evaluates (validate/micrograin/micrograin_brdf_models.cpp). For tests of
// those averages against an independent quadrature.
#include <string>

#include "models/core/vec.h"
#include "sim/experiment/experiment.h"

namespace mcref {

// Throws std::invalid_argument for an unknown or measured-V_p (*_simvp) model.
void micrograin_brdf_value(const std::string& model, const Experiment& ex, Vec3 i, Vec3 o, double out[3]);

}  // namespace mcref
