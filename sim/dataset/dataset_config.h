#pragma once
// A dataset file (TOML): a base experiment and the parameters that vary from
// entry to entry. Errors are ConfigError naming the file, key and allowed range.
//
//   [dataset]
//   experiment = "base.toml"     # base experiment, relative to this file
//   entries = 4000               # sampled entries per grid point (default 1;
//                                # required when a parameter is sampled)
//   seed = 2022                  # entries are a function of (seed, entry index)
//   tables = ["brdf", ...]       # tables kept per entry (default: all)
//   compression = 0              # gzip level 0..9 of the entry tables
//
//   [[parameter]]                # one per varied key, in this order
//   key = "geometry.layer.0.alpha"   # any experiment key path (--set syntax)
//   values = [0.1, 0.3]          # a grid axis (numbers, strings, arrays, inline tables)
//   # or sampled per entry:
//   range = [0.05, 1.0]          # with distribution = "uniform" (default) or "log_uniform";
//   size = 3                     #   size > 1 draws an array (e.g. RGB albedo)
//   choices = ["sggx_surface", "sggx_fiber"]   # uniform among values
//   distribution = "direction"   # unit vector, uniform on the upper hemisphere
//
// key = "<array>.count" (e.g. "geometry.layer.count") keeps the first n
// elements of an array of the base experiment (values or choices, integers in
// [1, base length]); parameters of dropped elements do not apply to the entry
// (NaN in the parameter table).
#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/files/input_file.h"

namespace mcref {

struct DatasetParameter {
  enum class Mode { kGrid, kUniform, kLogUniform, kChoice, kDirection };
  std::string key;
  Mode mode = Mode::kGrid;
  toml::array values;                            // kGrid, kChoice: the values as given
  std::vector<std::vector<double>> numeric;      // the same as numbers (empty if categorical)
  std::vector<std::string> labels;               // categorical: one label per value
  double lo = 0, hi = 0;                         // kUniform, kLogUniform
  int size = 1;                                  // components drawn (kUniform, kLogUniform)

  bool sampled() const { return mode != Mode::kGrid; }
  bool categorical() const { return (mode == Mode::kGrid || mode == Mode::kChoice) && numeric.empty(); }
  bool is_count() const;
  std::string count_array() const;  // "<array>" of "<array>.count"
  int width() const;                // number of columns in the parameter table
  std::vector<std::string> column_names() const;
};

struct DatasetConfig {
  std::string file;             // the dataset file (for messages)
  std::string text;             // canonical text of the dataset file (identity, provenance)
  std::string experiment;       // dataset.experiment as written
  std::string experiment_file;  // the base experiment, resolved against the dataset file
  std::string experiment_text;  // canonical text of the base experiment (and its inputs' contents)
  std::vector<InputFile> inputs;  // the base experiment's own input files (geometry.density_vdb)
  toml::table base;             // the base experiment, parsed
  std::uint64_t seed = 1;
  std::int64_t per_point = 1;   // sampled entries per grid point
  std::vector<std::string> tables;
  int compression = 0;
  std::vector<DatasetParameter> parameters;

  std::int64_t grid_points() const;
  std::int64_t entries() const { return grid_points() * per_point; }
  std::vector<std::string> column_names() const;
};

// A TOML value as text, on one line (inline tables and arrays).
std::string toml_text(const toml::node& node);

DatasetConfig parse_dataset(const std::string& text, const std::string& file);
DatasetConfig load_dataset(const std::string& path);

}  // namespace mcref
