#include "sim/hdf5/table_group.h"

#include <hdf5_hl.h>

#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "sim/hdf5/h5_util.h"

namespace mcref {

namespace {
const std::set<std::string> kReservedAttrs{"quantity", "units", "description", "batches", "axes", "storage"};

// netCDF-4's name for a dimension without a coordinate variable (bnds below).
const char* const kBoundsDimension = "This is a netCDF dimension but not a netCDF variable.         2";

// Bin edges from CF bounds (n x 2, lower and upper per bin); the bins must be contiguous.
std::vector<double> edges_from_bounds(const std::vector<double>& b, const std::string& name) {
  if (b.size() < 2 || b.size() % 2) throw std::runtime_error(name + " is not an (n, 2) array");
  std::vector<double> edges;
  for (std::size_t i = 0; i < b.size(); i += 2) {
    if (i > 0 && b[i] != b[i - 1]) throw std::runtime_error(name + ": the bins are not contiguous");
    edges.push_back(b[i]);
  }
  edges.push_back(b.back());
  return edges;
}
}  // namespace

bool reserved_table_attribute(const std::string& name) { return kReservedAttrs.count(name) > 0; }

std::vector<std::string> axis_labels(const Table& t, const Axis& a) {
  if (a.name == "channel" && a.size() == 3) return {"R", "G", "B"};
  const auto names = t.attributes.find("components");
  if (a.name != "component" || names == t.attributes.end()) return {};
  std::vector<std::string> out;
  std::stringstream ss(names->second);
  for (std::string n; std::getline(ss, n, ',');) out.push_back(n);
  return out.size() == a.size() ? out : std::vector<std::string>{};
}

void write_table_group(hid_t parent, const Table& t, int compression, TableStorage storage) {
  const bool lean = storage == TableStorage::kLean, sums = storage == TableStorage::kSums;
  h5::Handle group = h5::create_group(parent, t.name);
  h5::write_string_attr(group, "quantity", t.quantity);
  h5::write_string_attr(group, "units", t.units);
  h5::write_string_attr(group, "description", t.description);
  h5::write_int_attr(group, "batches", t.batches);
  std::string axes;
  for (const Axis& a : t.axes) axes += (axes.empty() ? "" : ",") + a.name;
  h5::write_string_attr(group, "axes", axes);
  for (const auto& [k, v] : t.attributes) h5::write_string_attr(group, k, v);
  if (lean || sums) h5::write_string_attr(group, "storage", lean ? "lean" : "sums");
  std::vector<hsize_t> dims;
  for (std::size_t n : t.shape()) dims.push_back(n);
  std::vector<h5::Handle> data;
  std::vector<int> kinds;  // of each dataset: 0 value, 1 stderr, 2 sum, 3 sum_sq
  if (lean) {
    data.push_back(h5::write_floats(group, "value", dims, t.values(), compression));
    data.push_back(h5::write_floats(group, "stderr", dims, t.stderrs(), compression));
    kinds = {0, 1};
  } else {
    if (!sums) {
      data.push_back(h5::write_doubles(group, "value", dims, t.values(), compression));
      data.push_back(h5::write_doubles(group, "stderr", dims, t.stderrs(), compression));
    }
    data.push_back(h5::write_doubles(group, "sum", dims, t.sum, compression));
    data.push_back(h5::write_doubles(group, "sum_sq", dims, t.sum_sq, compression));
    kinds = sums ? std::vector<int>{2, 3} : std::vector<int>{0, 1, 2, 3};
  }
  // Each batch's estimates, batch first (full storage, when the table kept them).
  std::optional<h5::Handle> per_batch, batch_scale;
  if (!lean && !sums && t.has_batch_values() && t.batches > 0) {
    std::vector<hsize_t> bdims{static_cast<hsize_t>(t.batches)};
    bdims.insert(bdims.end(), dims.begin(), dims.end());
    per_batch.emplace(h5::write_doubles(group, "batch_values", bdims, t.batch_values, compression));
    h5::write_string_attr(*per_batch, "long_name", "each batch's estimate of " + t.quantity);
    h5::write_string_attr(*per_batch, "units", t.units);
    std::vector<double> index(static_cast<std::size_t>(t.batches));
    for (std::size_t b = 0; b < index.size(); ++b) index[b] = static_cast<double>(b);
    batch_scale.emplace(h5::write_doubles(group, "batch", {index.size()}, index));
    h5::write_string_attr(*batch_scale, "units", "1");
    h5::check(H5DSset_scale(*batch_scale, "batch"), "making a dimension scale");
    h5::check(H5DSattach_scale(*per_batch, *batch_scale, 0), "attaching a scale");
  }
  // CF names: units and long_name on the data, auxiliary label coordinates.
  std::string labelled;
  for (const Axis& a : t.axes)
    if (!axis_labels(t, a).empty()) labelled += (labelled.empty() ? "" : " ") + a.name + "_label";
  const char* long_names[] = {"mean over batches", "standard error of the mean", "sum over batches",
                              "sum of squares over batches"};
  for (std::size_t i = 0; i < data.size(); ++i) {
    h5::write_string_attr(data[i], "long_name", std::string(long_names[kinds[i]]) + " of " + t.quantity);
    if (kinds[i] < 3) h5::write_string_attr(data[i], "units", t.units);  // (sum_sq: the square of units)
    if (!labelled.empty()) h5::write_string_attr(data[i], "coordinates", labelled);
  }
  // The size-2 dimension of the bounds, in groups with a binned axis.
  bool binned = false;
  for (const Axis& a : t.axes) binned = binned || a.kind == Axis::Kind::Bins;
  h5::Handle bnds = binned ? h5::write_doubles(group, "bnds", {2}, {0, 1}) : h5::Handle(-1, H5Dclose);
  if (binned) h5::check(H5DSset_scale(bnds, kBoundsDimension), "making the bounds dimension");
  for (std::size_t d = 0; d < t.axes.size(); ++d) {
    const Axis& a = t.axes[d];
    std::vector<double> pts(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) pts[i] = a.centre(i);
    h5::Handle scale = h5::write_doubles(group, a.name, {a.size()}, pts);
    h5::write_string_attr(scale, "units", a.unit);
    h5::check(H5DSset_scale(scale, a.name.c_str()), "making a dimension scale");
    for (const h5::Handle& ds : data)
      h5::check(H5DSattach_scale(ds, scale, static_cast<unsigned>(d)), "attaching a scale");
    if (per_batch) h5::check(H5DSattach_scale(*per_batch, scale, static_cast<unsigned>(d + 1)), "attaching a scale");
    if (a.kind == Axis::Kind::Bins) {
      std::vector<double> b;
      for (std::size_t i = 0; i < a.size(); ++i) b.insert(b.end(), {a.lower(i), a.upper(i)});
      h5::Handle bounds = h5::write_doubles(group, a.name + "_bounds", {a.size(), 2}, b);
      h5::write_string_attr(bounds, "units", a.unit);
      h5::write_string_attr(scale, "bounds", a.name + "_bounds");
      h5::check(H5DSattach_scale(bounds, scale, 0), "attaching a scale");
      h5::check(H5DSattach_scale(bounds, bnds, 1), "attaching a scale");
    }
    const std::vector<std::string> labels = axis_labels(t, a);
    if (!labels.empty()) {
      h5::Handle label = h5::write_strings(group, a.name + "_label", labels);
      h5::check(H5DSattach_scale(label, scale, 0), "attaching a scale");
    }
  }
}

std::string table_group_storage(hid_t parent, const std::string& name) {
  h5::Handle group = h5::open_group(parent, name);
  return h5::has_attr(group, "storage") ? h5::read_string_attr(group, "storage") : "full";
}

Table read_table_group(hid_t parent, const std::string& name) {
  h5::Handle group = h5::open_group(parent, name);
  const std::string storage = h5::has_attr(group, "storage") ? h5::read_string_attr(group, "storage") : "full";
  if (storage == "lean")
    throw std::runtime_error("table " + name + " is lean storage (float32 value and stderr, no sums): it cannot be merged or resumed");
  if (storage != "full" && storage != "sums")
    throw std::runtime_error("table " + name + " has an unknown storage \"" + storage + "\"");
  std::vector<Axis> axes;
  std::stringstream ss(h5::read_string_attr(group, "axes"));
  for (std::string a; std::getline(ss, a, ',');) {
    for (const Axis& seen : axes)
      if (seen.name == a) throw std::runtime_error("table " + name + " names axis " + a + " twice");
    h5::Handle scale(H5Dopen2(group, a.c_str(), H5P_DEFAULT), H5Dclose);
    if (!scale.valid()) throw std::runtime_error("missing axis " + a);
    // ("unit" and "<axis>_edges": files from before the CF names)
    const std::string unit = h5::read_string_attr(scale, h5::has_attr(scale, "units") ? "units" : "unit");
    if (h5::exists(group, a + "_bounds"))
      axes.push_back(Axis::bins(a, unit, edges_from_bounds(h5::read_doubles(group, a + "_bounds"), a + "_bounds")));
    else if (h5::exists(group, a + "_edges"))
      axes.push_back(Axis::bins(a, unit, h5::read_doubles(group, a + "_edges")));
    else
      axes.push_back(Axis::points(a, unit, h5::read_doubles(group, a)));
  }
  Table t(name, h5::read_string_attr(group, "quantity"), axes);
  t.units = h5::read_string_attr(group, "units");
  t.description = h5::read_string_attr(group, "description");
  t.batches = h5::read_int_attr(group, "batches");
  const std::size_t cells = t.cells();  // the product of the axes' sizes (the constructor's zeros)
  t.sum = h5::read_doubles(group, "sum");
  t.sum_sq = h5::read_doubles(group, "sum_sq");
  if (t.sum.size() != cells || t.sum_sq.size() != cells)
    throw std::runtime_error("table " + name + ": sum holds " + std::to_string(t.sum.size()) + " values, its axes " +
                             std::to_string(cells) + " cells");
  // value and stderr are derived from the sums (and not stored in "sums"); a
  // full table whose stored ones are missing or differ (bit for bit, NaN as
  // NaN) is damaged or not mcref's.
  for (const char* derived : {"value", "stderr"}) {
    if (storage != "full") continue;
    if (!h5::exists(group, derived)) throw std::runtime_error("table " + name + " has no " + derived + " dataset");
    const std::vector<double> stored = h5::read_doubles(group, derived);
    if (stored.size() != t.cells()) throw std::runtime_error("table " + name + ": " + derived + " has the wrong shape");
    for (std::size_t i = 0; i < stored.size(); ++i) {
      const double expect = derived[0] == 'v' ? t.value(i) : t.stderr_of(i);
      // (Files from before empty cells had NaN stderr stored 0 there.)
      const bool empty_cell = std::isnan(expect) && (std::isnan(stored[i]) || (derived[0] == 's' && stored[i] == 0));
      if (!(stored[i] == expect || empty_cell))
        throw std::runtime_error("table " + name + ": " + derived + " does not match its sums (damaged?)");
    }
  }
  // Batch values: their sums in batch order are the stored sums, bit for bit.
  if (storage == "full" && h5::exists(group, "batch_values")) {
    t.batch_values = h5::read_doubles(group, "batch_values");
    t.keep_batch_values = true;
    if (t.batches < 1 || t.batch_values.size() != static_cast<std::size_t>(t.batches) * t.cells())
      throw std::runtime_error("table " + name + ": batch_values has the wrong shape");
    std::vector<double> sum(t.cells(), 0.0);
    for (std::size_t b = 0; b < static_cast<std::size_t>(t.batches); ++b)
      for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += t.batch_values[b * sum.size() + i];
    for (std::size_t i = 0; i < sum.size(); ++i)
      if (!(sum[i] == t.sum[i] || (std::isnan(sum[i]) && std::isnan(t.sum[i]))))
        throw std::runtime_error("table " + name + ": batch_values do not add up to sum (damaged?)");
  }
  H5O_info_t info;
  h5::check(H5Oget_info(group, &info), "reading a group's attributes");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    h5::Handle attr(H5Aopen_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    const ssize_t len = H5Aget_name(attr, 0, nullptr);
    std::string key(static_cast<std::size_t>(len), '\0');
    H5Aget_name(attr, key.size() + 1, key.data());
    if (!kReservedAttrs.count(key)) t.attributes[key] = h5::read_string_attr(group, key);
  }
  return t;
}

}  // namespace mcref
