#pragma once
// HDF5 dataset files (format "mcref-dataset", version 1): the parameters and
// the tables of many entries of one dataset config.
//
//   /                       attributes: mcref_format, format_version, mcref_version,
//                           git_commit, sim_fingerprint, seed, entries (in the whole dataset),
//                           shard ("all", "K/N" or "part"), compression,
//                           dataset_config, experiment_config, experiment_file,
//                           conventions, layout; storage = "lean" in lean files,
//                           "sums" in parts (absent: full)
//   /parameters/values      float64 [rows, columns]: one row per entry in this file,
//                           NaN where a parameter does not apply (e.g. layer 1
//                           of a 1-layer entry); categorical columns hold an index
//                           into /parameters/labels/<column>
//   /parameters/names       string [columns]
//   /parameters/index       int64 [rows]: the entry index of each row
//   /parameters/seed        int64 [rows]: run.seed each entry was simulated with
//   /parameters/assignments string [rows]: the entry's key=value settings, one a line
//   /parameters/labels/<column>   string: labels of a categorical column
//   /entries/<index>/       attributes index, seed, assignments, config (the entry's
//                           effective experiment); one group per table in the
//                           layout of sim/hdf5/table_file.h (value, stderr, sum,
//                           sum_sq, axes as dimension scales, <axis>_bounds); in
//                           lean files value and stderr only, as float32
//                           (sim/hdf5/table_group.h): such files cannot be merged
//                           or resumed, entry() refuses them; in sums files
//                           (storage = "sums": the parts of a dataset being
//                           computed) sum and sum_sq only
// No wall-clock dates nor command lines are stored and object time tracking
// is off, so a file's bytes are a function of its content; the writer takes
// entries in increasing index order (canonical). Files are written to a
// temporary name and renamed into place.
#include <hdf5.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sim/files/temp_file.h"
#include "sim/tally/table.h"

namespace mcref {

struct DatasetHeader {
  std::string mcref_version, git_commit;
  // Of the build that simulated the entries (sim/hdf5/table_file.h); empty in
  // files from before it. The git commit is provenance only, not compared.
  std::string sim_fingerprint;
  std::uint64_t seed = 0;
  std::int64_t entries = 0;
  std::string shard = "all";
  int compression = 0;
  std::string dataset_config, experiment_config, experiment_file;
  std::vector<std::string> columns;
  std::map<std::string, std::vector<std::string>> labels;  // categorical columns
  bool lean = false;  // float32 value and stderr, no sums (final files only)
  // sum and sum_sq only, value and stderr derived when read (the parts of a
  // dataset being computed: half the bytes); not compared by difference().
  bool sums = false;

  // Same dataset (config, base, seed, simulation fingerprint): shards and parts may be combined.
  bool same_dataset(const DatasetHeader& o) const;
  // Why not, in a few words ("" if same_dataset).
  std::string difference(const DatasetHeader& o) const;
};

struct DatasetEntry {
  std::int64_t index = 0;
  std::uint64_t seed = 0;
  std::vector<double> parameters;  // one per column
  std::string assignments;         // key=value lines
  std::string config;              // effective experiment text
  std::vector<Table> tables;
};

class DatasetWriter {
 public:
  DatasetWriter(const std::string& path, const DatasetHeader& header);
  ~DatasetWriter();  // removes the temporary file unless committed
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;
  // Entries in strictly increasing index order.
  void add(const DatasetEntry& entry);
  // Writes the parameter table, closes and renames into place.
  void commit();

 private:
  template <class Write>
  void guarded(const Write& write);  // HDF5 failures as one line naming the output
  void write_entry(const DatasetEntry& entry);
  void write_parameters_and_close();

  std::string path_;
  TempFile tmp_;  // <path>.tmp.<pid>, renamed over path_ by commit()
  DatasetHeader header_;
  hid_t file_ = -1, entries_ = -1;
  std::vector<DatasetEntry> rows_;  // parameters only (tables dropped)
};

class DatasetReader {
 public:
  // Throws ConfigError (file, reason) if unreadable or not an mcref dataset.
  explicit DatasetReader(const std::string& path);
  ~DatasetReader();
  DatasetReader(const DatasetReader&) = delete;
  DatasetReader& operator=(const DatasetReader&) = delete;
  const DatasetHeader& header() const { return header_; }
  const std::vector<std::int64_t>& indices() const { return indices_; }
  // Throws ConfigError for a lean file (its tables have no sums).
  DatasetEntry entry(std::int64_t index) const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  hid_t file_ = -1;
  DatasetHeader header_;
  std::vector<std::int64_t> indices_;
  std::vector<std::uint64_t> seeds_;
  std::vector<std::string> assignments_;
  std::vector<double> values_;
};

}  // namespace mcref
