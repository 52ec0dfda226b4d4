#pragma once
// One Table as an HDF5 group, in the layout of sim/hdf5/table_file.h:
//   <group>/value, stderr, sum, sum_sq  (N-d float64), attributes quantity,
//   units, description, batches, axes and the table's notes; one dimension
//   scale per axis (bin centres or points) and <axis>_bounds for binned axes,
//   with the netCDF-CF names xarray and netCDF tools read (table_file.h).
// Files from before the CF names (<axis>_edges, attribute unit) still read.
// Written without time tracking (see h5_util.h), optionally gzip-compressed.
//
// A table that kept its batch values (Table::batch_values) has them as
// batch_values (batches x N-d, float64), with the dimension scale batch
// (0, 1, ...); reading checks that they add up to sum, bit for bit.
//
// Two other storages, each marked by the group's attribute storage:
// - "lean" (paper-scale datasets that will not be merged further): value and
//   stderr as float32, no sum nor sum_sq. Such a table cannot be read back as a
//   Table (the sums are gone): read_table_group refuses it, saying so.
// - "sums" (the parts of a dataset being computed, read back by mcref only):
//   sum and sum_sq alone, half the bytes; value and stderr follow from them.
#include <hdf5.h>

#include <string>
#include <vector>

#include "sim/tally/table.h"

namespace mcref {

enum class TableStorage { kFull, kLean, kSums };
// The group attributes the layout itself uses (quantity, units, description,
// batches, axes, storage): a table's notes cannot take these names.
bool reserved_table_attribute(const std::string& name);
void write_table_group(hid_t parent, const Table& table, int compression, TableStorage storage = TableStorage::kFull);
// The group's storage attribute: "lean" or "sums", or "full" when absent.
std::string table_group_storage(hid_t parent, const std::string& name);
Table read_table_group(hid_t parent, const std::string& name);
// Text labels of an index axis, stored as the auxiliary coordinate
// "<axis>_label": R, G, B for the channel axis, the table's `components`
// attribute for the component axis; empty for other axes.
std::vector<std::string> axis_labels(const Table& t, const Axis& a);

}  // namespace mcref
