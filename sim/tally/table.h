#pragma once
// A table of per-batch estimates: for every cell, the sum and the sum of
// squares of one estimate per batch (one batch = one independent realization
// of the random geometry), and the batch count. value = mean over batches;
// stderr = sample standard deviation / sqrt(batches), so the error bar covers
// both path noise and realization-to-realization variance. Tables from
// shards or reruns merge exactly by adding sums.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace mcref {

// The `empty_cells` attribute of tables whose cells can be empty: a ratio
// whose denominator was 0 in some batch (tau0 near 0 or 1, few samples).
constexpr const char* kEmptyCellsNote = "NaN value and NaN stderr where a batch had no sample in the cell";

// One axis of a table: either bins (edges, n+1 values) or a list of points
// (e.g. the incident directions the user asked for).
struct Axis {
  enum class Kind { Bins, Points };
  std::string name;  // e.g. "theta_i", "theta_m", "r"
  std::string unit;  // e.g. "rad", "1", "radius"
  Kind kind = Kind::Points;
  std::vector<double> values;  // points, or bin edges

  static Axis bins(std::string name, std::string unit, std::vector<double> edges);
  static Axis uniform_bins(std::string name, std::string unit, double lo, double hi, int n);
  static Axis points(std::string name, std::string unit, std::vector<double> values);
  std::size_t size() const { return kind == Kind::Bins ? values.size() - 1 : values.size(); }
  double centre(std::size_t i) const {
    return kind == Kind::Bins ? 0.5 * (values[i] + values[i + 1]) : values[i];
  }
  double lower(std::size_t i) const { return values[i]; }
  double upper(std::size_t i) const { return kind == Kind::Bins ? values[i + 1] : values[i]; }
  // Bin index of x (Bins only), or -1 outside [edges.front(), edges.back()).
  int find_bin(double x) const;
  bool operator==(const Axis& o) const {
    return name == o.name && unit == o.unit && kind == o.kind && values == o.values;
  }
};

// Attributes that count events over batches (integers), e.g. the phase
// estimator's rays that missed every sphere.
inline const char* const kCountAttributes[] = {"missed_rays"};

struct Table {
  std::string name;       // group name in the HDF5 file
  std::string quantity;   // "p1", "ndf", "tau_plus", ...
  std::string units;      // of `value`, e.g. "1/sr", "1"
  std::string description;
  std::vector<Axis> axes;  // row-major: the last axis varies fastest
  std::vector<double> sum, sum_sq;
  std::int64_t batches = 0;
  // Each batch's estimates, batch after batch (batches x cells, row-major),
  // when kept (SimulateOptions::keep_batch_values; table files store them as
  // batch_values): the verdicts estimate the cells' correlation from them
  // (validate/metrics.h). Kept tables append a merged one-batch table's sums,
  // or a merged table's own batch values; merging one without drops them all.
  bool keep_batch_values = false;
  std::vector<double> batch_values;
  std::map<std::string, std::string> attributes;  // extra notes stored with the table

  Table() = default;
  Table(std::string name, std::string quantity, std::vector<Axis> axes);
  std::size_t cells() const { return sum.size(); }
  std::vector<std::size_t> shape() const;
  // Colour channels: the size of the last axis if it is "channel", else 1. A
  // path's channels are one sample, not independent cells (validate/metrics.h
  // judges each channel's chi-squared on its own).
  std::size_t channels() const { return !axes.empty() && axes.back().name == "channel" ? axes.back().size() : 1; }
  // Row-major flat index of a multi-index.
  std::size_t index(const std::vector<std::size_t>& idx) const;
  // Adds one batch's estimates (one per cell).
  void add_batch(const std::vector<double>& estimate);
  // Adds another table's batches (same name, axes); exact merge. Count
  // attributes (kCountAttributes) add up; other attributes missing here are
  // taken from `other`. Batch values: see keep_batch_values.
  void merge(const Table& other);
  // Batch values for every batch (so the verdicts can use them).
  bool has_batch_values() const { return keep_batch_values && batch_values.size() == static_cast<std::size_t>(batches) * cells(); }
  double value(std::size_t i) const;
  double stderr_of(std::size_t i) const;
  std::vector<double> values() const;
  std::vector<double> stderrs() const;
};

}  // namespace mcref
