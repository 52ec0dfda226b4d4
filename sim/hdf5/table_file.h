#pragma once
// HDF5 table files. Layout (format "mcref-tables", version 1):
//   /                      attributes: mcref_format, format_version, mcref_version,
//                          git_commit, sim_fingerprint, created, command_line,
//                          seed, config, source_file, conventions
//   /<table>/              one group per table; attributes: quantity, units,
//                          description, batches, axes (comma-separated, in
//                          dimension order) and any table-specific notes
//   /<table>/value         mean over batches            (N-d, float64)
//   /<table>/stderr        standard error of the mean   (N-d)
//   /<table>/sum, sum_sq   raw sums over batches        (N-d)
//   /<table>/batch_values  each batch's estimates, (batches, N-d), with the
//                          dimension scale /<table>/batch (0, 1, ...); only
//                          in tables that kept them (mcref validate's)
//     (each with long_name; value, stderr and sum with units; coordinates
//     naming the label datasets below, if any)
//   /<table>/<axis>        axis points or bin centres: HDF5 dimension scales
//                          attached to the data; attributes units, and bounds
//                          on binned axes
//   /<table>/<axis>_bounds bin bounds (binned axes only), (n, 2): lower, upper
//   /<table>/bnds          the size-2 dimension of the bounds (netCDF-4's
//                          dimension without a variable)
//   /<table>/channel_label "R", "G", "B"; component_label: the components
// These are the netCDF-CF names: xarray (engine h5netcdf) opens a table with
// xarray.open_dataset(path, group=<table>). Files written before them (unit,
// <axis>_edges) still read.
// Files are written to a temporary name and renamed into place, so a failed
// write never leaves a half-written file nor replaces a good one.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/tally/table.h"

namespace mcref {

struct Provenance {
  std::string mcref_version, git_commit, created, command_line, config, source_file;
  std::string sim_fingerprint;  // of the build that simulated (empty in files from before it)
  std::uint64_t seed = 0;
};

struct TableFile {
  Provenance provenance;
  std::vector<Table> tables;
  const Table* find(const std::string& name) const;
};

// The conventions every file states (DESIGN.md).
const char* table_conventions();
std::string mcref_version();
std::string mcref_git_commit();
// The simulation fingerprint of this build (scripts/sim_fingerprint.cmake): it
// changes with anything that can change what a simulation computes.
std::string mcref_sim_fingerprint();
// Provenance for a run now: version, commit, UTC date (SOURCE_DATE_EPOCH if set), command line.
Provenance make_provenance(const std::string& config_text, const std::string& source_file, std::uint64_t seed,
                           const std::string& command_line);

void write_table_file(const std::string& path, const TableFile& file);
// Throws ConfigError (file, reason) if unreadable or not written by mcref.
TableFile read_table_file(const std::string& path);

}  // namespace mcref
