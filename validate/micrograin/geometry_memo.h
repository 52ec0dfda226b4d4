#pragma once
// The G_dist diffuse geometry factor (micrograin_bsdf.h), memoised. Several
// models of one table evaluate it at the same quadrature nodes: gdist_grain,
// gdist_total and gdist_total_simvp (product masking), gdist_grain_union and
// gdist_total_union (union masking), and the albedo models likewise; each
// (field, i, o, ior, masking) is computed once per process. It is a pure
// function, so the result does not depend on which check computes it first.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/micrograin_bsdf.h"

namespace mcref {

double memo_diffuse_geometry(const micrograin::GrainField& f, Vec3 i, Vec3 o, double ior, micrograin::TwoWay masking);

}  // namespace mcref
