#pragma once
// What a run will produce and hold, known before anything is simulated:
// the (empty) tables of an experiment, and an estimate of the memory its
// tables take, checked against a budget so that an oversize run is refused
// up front with one line instead of ending in std::bad_alloc.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/tally/table.h"

namespace mcref {

// The tables simulate() returns for `ex`, in the same order, with no batch.
// Call check_memory first: they are allocated.
std::vector<Table> empty_tables(const Experiment& ex);
// The same tables (names, quantities, axis names, attributes) with every
// bin count of the measures at its smallest: cheap to make whatever the run's
// size, for checks of what a run will write.
std::vector<Table> table_outline(const Experiment& ex);

// ConfigError(file, key, ...) naming the first of `names` that is not a table
// of the experiment, and the tables it writes (where a caller asks for tables
// by name: a dataset's `tables`, simulate's --table).
void check_table_names(const Experiment& ex, const std::vector<std::string>& names, const std::string& file,
                       const std::string& key);

// The same for a table given whole (one built in Python): it must also be laid
// out as the experiment's table of that name, with its quantity and its axes'
// names, kinds and units in order (their values and sizes may differ), since
// the models read the axes by position.
void check_table_layout(const Experiment& ex, const Table& table, const std::string& file, const std::string& key);

// Cells of a measure's tables, from the measure alone (nothing allocated):
// an upper bound of the cells of its empty_tables (small derived tables are
// counted even where they are not written).
double measure_cells(const Measure& m, const Experiment& ex);

// The threads simulate() runs on: `requested` if > 0, else run.threads if
// > 0, else every core.
int effective_threads(const Experiment& ex, int requested);

// Estimated peak memory of simulating `ex` on `threads` threads, in bytes:
// per table cell 48 bytes (sum, sum_sq, one batch's estimates and copies, as
// the sphere walks hold them; the value and stderr written), plus one chunk
// tally per thread (and two more) of the measure's largest per-direction
// tally, 8 bytes a number; with `keep_batch_values`, 8 bytes per cell and
// batch more (sim/tally/table.h).
double memory_needed(const Experiment& ex, int threads, bool keep_batch_values = false);

// The memory a run may plan for, in bytes: MCREF_MEMORY_LIMIT (bytes, with an
// optional suffix K, M, G or T, powers of 1024) if set, else half the physical
// memory, or half the cgroup's memory.max when that is lower. `why` (if given)
// receives how the budget was set, for messages.
double memory_budget(std::string* why = nullptr);

// ConfigError naming the file, the keys of the largest measure and the size
// needed, if memory_needed(ex, effective_threads(ex, requested_threads))
// exceeds memory_budget().
void check_memory(const Experiment& ex, int requested_threads, bool keep_batch_values = false);

// One number of bytes as text: "3.2 GB" (powers of 1024: KB, MB, GB, TB).
std::string bytes_text(double bytes);

}  // namespace mcref
