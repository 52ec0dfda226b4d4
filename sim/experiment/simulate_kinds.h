#pragma once
// One simulate function per geometry kind (simulate() dispatches on kind).
// Each runs run.batches realizations through `loop` (which may spread them
// over ranks) and returns its tables; a batch advances loop.progress() by
// the caller-agreed work units (see work_units()).
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/parallel/batch_loop.h"
#include "sim/tally/table.h"

namespace mcref {

// Work units of one batch of one measure (samples x directions), for progress.
double work_units(const Measure& m);
// The tables of every measure, in measure order, as one list.
std::vector<Table> flatten(std::vector<std::vector<Table>>&& per_measure);

// The empty tables of every measure (one list per measure), as the
// simulate_<kind> below fill them.
BatchLoop::Tables micrograin_tables(const Experiment& ex);
// (`keep`: SimulateOptions::tables; the slab's BRDF tables it does not name
// are made without cells and not filled.)
BatchLoop::Tables slab_tables(const Experiment& ex, const std::vector<std::string>& keep = {});
BatchLoop::Tables sphere_tables(const Experiment& ex);

std::vector<Table> simulate_micrograin(const Experiment& ex, const BatchLoop& loop, std::size_t* grains);
std::vector<Table> simulate_slab(const Experiment& ex, const BatchLoop& loop, const std::vector<std::string>& keep);
std::vector<Table> simulate_spheres(const Experiment& ex, const BatchLoop& loop);

}  // namespace mcref
