#pragma once
// Measures of a Lambertian-sphere volume (kind = "spheres"):
//   brdf:  the tables of sim/tally/brdf_tally.h (order-1 class "sphere") plus
//          <name>_transmittance, the energy leaving through the bottom of the
//          slab per incident direction and channel (the depth check);
//   phase: <name>, parallel rays on one Lambertian sphere, one bounce,
//          density of the deflection cosine mu (Eq. 1: 2 pi p(mu)).
// Each add_*_batch adds one batch (one realization) to its tables, sampling in
// deterministic chunks (run_chunks), so tables do not depend on thread count.
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/parallel/run_chunks.h"
#include "sim/tally/brdf_tally.h"
#include "sim/tally/table.h"

namespace mcref {

class SphereField;

BrdfLayout sphere_brdf_layout(const Measure& m, const Experiment& ex);
std::vector<Table> make_sphere_brdf_tables(const Measure& m, const Experiment& ex);
// field == nullptr: the volumetric half-space (placement = "volumetric").
void add_sphere_brdf_batch(const SphereField* field, const Experiment& ex, const Measure& m, const StreamKey& key,
                           std::vector<Table>& tables);

std::vector<Table> make_phase_tables(const Measure& m, const Experiment& ex);
void add_phase_batch(const Experiment& ex, const Measure& m, const StreamKey& key, std::vector<Table>& tables);

}  // namespace mcref
