#pragma once
// One Table as an HDF5 group, in the layout of sim/hdf5/table_file.h:
//   <group>/value, stderr, sum, sum_sq  (N-d float64), attributes quantity,
//   units, description, batches, axes and the table's notes; one dimension
//   scale per axis (bin centres or points) and <axis>_bounds for binned axes,
//   with the netCDF-CF names xarray and netCDF tools read (table_file.h).
// Files from before the CF names (<axis>_edges, attribute unit) still read.
// Written without time tracking (see h5_util.h), optionally gzip-compressed.
//
// Lean storage (paper-scale datasets that will not be merged further): value
// and stderr as float32, no sum nor sum_sq, and the attribute storage = "lean"
// marking it. Such a table cannot be read back as a Table (the sums are gone):
// read_table_group refuses it with a message that says so.
#include <hdf5.h>

#include <string>
#include <vector>

#include "sim/tally/table.h"

namespace mcref {

void write_table_group(hid_t parent, const Table& table, int compression, bool lean = false);
// The group's storage attribute: "lean", or "full" when absent.
std::string table_group_storage(hid_t parent, const std::string& name);
Table read_table_group(hid_t parent, const std::string& name);
// Text labels of an index axis, stored as the auxiliary coordinate
// "<axis>_label": R, G, B for the channel axis, the table's `components`
// attribute for the component axis; empty for other axes.
std::vector<std::string> axis_labels(const Table& t, const Axis& a);

}  // namespace mcref
