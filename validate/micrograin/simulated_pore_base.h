#pragma once
// The base term of the vNDF paper's Eq. 1, V_p(i, o) f_B(i, o) over the pore
// fraction 1 - tau0 of the base, with the bidirectional pore visibility V_p
// measured on an explicit field: its closed form is unknown (LRPB23 Eq. 24
// assumes that the visibilities from i and o are independent). For a single
// event on the base this is exact, so it is the order-1 base part of the
// simulation up to this estimate's own noise.
//
// Per table cell, a Monte Carlo average over kPorePoints pore points of one
// wide field (the experiment's grains on a tile of at least 400 radii, so
// that this one realisation is close to the ensemble; a fixed seed of its
// own) and, per point
// and cell, one outgoing direction drawn cosine-weighted inside the cell: no
// quadrature error at the hot spot, where V_p peaks. Relative noise about
// 1 % per cell, estimated per cell from the spread over pore points.
//   brdf tables:   (1 - tau0) <V_p f_B> per cell (1/sr), all channels;
//   albedo tables: (1 - tau0) [pi <V_p f_B>_cos + V_p(i, mirror i) E_delta]
//                  in the order1_base and total components, others NaN;
//   delta tables:  the delta part alone, in the same components.
#include <functional>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/tally/table.h"

namespace mcref {

struct BaseReflection {
  std::function<double(int channel, Vec3 i, Vec3 o)> brdf;      // f_B, 1/sr (no delta)
  std::function<double(int channel, Vec3 i)> delta_energy;       // energy of its mirror lobe
};

// The estimate and its per-cell standard errors (from the spread over pore
// points), cached per experiment and table shape.
struct PoreBase {
  std::vector<double> values, stderrs;
};
const PoreBase& simulated_pore_base(const Table& t, const Experiment& ex, const BaseReflection& base);

}  // namespace mcref
