#include "sim/dataset/dataset_file.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "sim/experiment/config_error.h"
#include "sim/files/temp_file.h"
#include "sim/hdf5/file_seal.h"
#include "sim/hdf5/h5_util.h"
#include "sim/hdf5/table_group.h"
#include "sim/hdf5/table_file.h"

namespace mcref {

namespace {

constexpr const char* kFormat = "mcref-dataset";
constexpr int kFormatVersion = 1;

const char* kLayout =
    "/parameters/values [rows, columns] float64 (NaN: does not apply; categorical columns: index into "
    "/parameters/labels/<column>), /parameters/names [columns], /parameters/index [rows] entry index, "
    "/parameters/seed [rows], /parameters/assignments [rows]; /entries/<index>/<table>/{value, stderr, sum, "
    "sum_sq, axes} as in mcref table files";
const char* kLeanLayout =
    "/parameters/values [rows, columns] float64 (NaN: does not apply; categorical columns: index into "
    "/parameters/labels/<column>), /parameters/names [columns], /parameters/index [rows] entry index, "
    "/parameters/seed [rows], /parameters/assignments [rows]; /entries/<index>/<table>/{value, stderr} "
    "float32 and axes as in mcref table files (lean storage: no sum, sum_sq)";
const char* kSumsLayout =
    "/parameters/values [rows, columns] float64 (NaN: does not apply; categorical columns: index into "
    "/parameters/labels/<column>), /parameters/names [columns], /parameters/index [rows] entry index, "
    "/parameters/seed [rows], /parameters/assignments [rows]; /entries/<index>/<table>/{sum, sum_sq, axes} "
    "as in mcref table files (sums storage: value = sum / batches, stderr from sum_sq, not stored)";

}  // namespace

bool DatasetHeader::same_dataset(const DatasetHeader& o) const { return difference(o).empty(); }

std::string DatasetHeader::difference(const DatasetHeader& o) const {
  if (seed != o.seed) return "the seeds differ (" + std::to_string(seed) + " vs " + std::to_string(o.seed) + ")";
  if (dataset_config != o.dataset_config) return "the dataset configs differ";
  if (experiment_config != o.experiment_config) return "the base experiments differ";
  if (entries != o.entries) return "the entry counts differ";
  if (columns != o.columns || labels != o.labels) return "the parameter columns differ";
  if (compression != o.compression) return "the compression levels differ";
  if (lean != o.lean) return std::string("one is lean storage, the other full (") + (lean ? "lean" : "full") + " vs " + (o.lean ? "lean" : "full") + ")";
  if (sim_fingerprint.empty() || sim_fingerprint != o.sim_fingerprint) {
    auto build = [](const DatasetHeader& h) {
      return "mcref " + h.mcref_version + " " + h.git_commit + ", simulation fingerprint " +
             (h.sim_fingerprint.empty() ? "none" : h.sim_fingerprint);
    };
    return "they were simulated by builds whose simulation differs (" + build(*this) + " vs " + build(o) + ")";
  }
  return "";
}

DatasetWriter::DatasetWriter(const std::string& path, const DatasetHeader& header)
    : path_(path), tmp_(path), header_(header) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  h5::Handle fcpl = h5::file_create_plist();
  file_ = H5Fcreate(tmp_.path().c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  if (file_ < 0) throw ConfigError(path, "", "cannot create the output file (is the directory writable?)");
  try {
    h5::Handle root = h5::open_group(file_, "/");
    h5::write_string_attr(root, "mcref_format", kFormat);
    h5::write_int_attr(root, "format_version", kFormatVersion);
    h5::write_string_attr(root, "mcref_version", header.mcref_version);
    h5::write_string_attr(root, "git_commit", header.git_commit);
    h5::write_string_attr(root, "sim_fingerprint", header.sim_fingerprint);
    h5::write_int_attr(root, "seed", static_cast<std::int64_t>(header.seed));
    h5::write_int_attr(root, "entries", header.entries);
    h5::write_string_attr(root, "shard", header.shard);
    h5::write_int_attr(root, "compression", header.compression);
    h5::write_string_attr(root, "dataset_config", header.dataset_config);
    h5::write_string_attr(root, "experiment_config", header.experiment_config);
    h5::write_string_attr(root, "experiment_file", header.experiment_file);
    h5::write_string_attr(root, "conventions", table_conventions());
    if (header.lean && header.sums) throw std::logic_error("a dataset file is lean or sums, not both");
    h5::write_string_attr(root, "layout", header.lean ? kLeanLayout : header.sums ? kSumsLayout : kLayout);
    if (header.lean || header.sums) h5::write_string_attr(root, "storage", header.lean ? "lean" : "sums");
    h5::Handle entries = h5::create_group(file_, "entries");
    entries_ = H5Gopen2(file_, "entries", H5P_DEFAULT);
  } catch (...) {
    H5Fclose(file_);
    throw;
  }
}

DatasetWriter::~DatasetWriter() {
  if (entries_ >= 0) H5Gclose(entries_);
  if (file_ >= 0) H5Fclose(file_);
}

// A failed HDF5 write (a full disk) as one line naming the output.
template <class Write>
void DatasetWriter::guarded(const Write& write) {
  try {
    write();
  } catch (const std::logic_error&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(path_ + ": writing failed (" + e.what() + "; disk full?)");
  }
}

void DatasetWriter::add(const DatasetEntry& e) {
  if (!rows_.empty() && e.index <= rows_.back().index)
    throw std::logic_error("dataset entries must be written in increasing index order");
  if (e.parameters.size() != header_.columns.size()) throw std::logic_error("entry has the wrong parameter count");
  guarded([&] { write_entry(e); });
  DatasetEntry row = e;
  row.tables.clear();
  row.config.clear();
  rows_.push_back(std::move(row));
}

void DatasetWriter::write_entry(const DatasetEntry& e) {
  h5::Handle g = h5::create_group(entries_, std::to_string(e.index));
  h5::write_int_attr(g, "index", e.index);
  h5::write_int_attr(g, "seed", static_cast<std::int64_t>(e.seed));
  h5::write_string_attr(g, "assignments", e.assignments);
  h5::write_string_attr(g, "config", e.config);
  std::vector<const Table*> tables;
  for (const Table& t : e.tables) tables.push_back(&t);
  std::sort(tables.begin(), tables.end(), [](const Table* a, const Table* b) { return a->name < b->name; });
  const TableStorage storage = header_.lean ? TableStorage::kLean : header_.sums ? TableStorage::kSums : TableStorage::kFull;
  for (const Table* t : tables) write_table_group(g, *t, header_.compression, storage);
}

void DatasetWriter::commit() {
  guarded([&] { write_parameters_and_close(); });
  seal_file(tmp_.path());
  tmp_.commit();
}

void DatasetWriter::write_parameters_and_close() {
  {
    h5::Handle p = h5::create_group(file_, "parameters");
    const std::size_t rows = rows_.size(), cols = header_.columns.size();
    std::vector<double> values;
    std::vector<std::int64_t> index, seed;
    std::vector<std::string> assignments;
    for (const DatasetEntry& r : rows_) {
      values.insert(values.end(), r.parameters.begin(), r.parameters.end());
      index.push_back(r.index);
      seed.push_back(static_cast<std::int64_t>(r.seed));
      assignments.push_back(r.assignments);
    }
    h5::write_doubles(p, "values", {rows, cols}, values);
    h5::write_strings(p, "names", header_.columns);
    h5::write_int64s(p, "index", index);
    h5::write_int64s(p, "seed", seed);
    h5::write_strings(p, "assignments", assignments);
    h5::Handle labels = h5::create_group(p, "labels");
    for (const auto& [column, names] : header_.labels) h5::write_strings(labels, column, names);
  }
  H5Gclose(entries_);
  entries_ = -1;
  h5::check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing");
  const herr_t closed = H5Fclose(file_);
  file_ = -1;
  h5::check(closed, "closing " + tmp_.path());
}

DatasetReader::DatasetReader(const std::string& path) : path_(path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (!std::filesystem::exists(path)) throw ConfigError(path, "", "no such file");
  check_seal(path);  // before HDF5 reads a byte of a damaged file
  if (H5Fis_hdf5(path.c_str()) <= 0) throw ConfigError(path, "", "not an HDF5 file");
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) throw ConfigError(path, "", "cannot open the HDF5 file");
  try {
    h5::Handle root = h5::open_group(file_, "/");
    if (!h5::has_attr(root, "mcref_format") || h5::read_string_attr(root, "mcref_format") != kFormat)
      throw ConfigError(path, "mcref_format", "not an mcref dataset file (root attribute mcref_format != \"mcref-dataset\")");
    const std::int64_t version = h5::read_int_attr(root, "format_version");
    if (version != kFormatVersion)
      throw ConfigError(path, "format_version", "is " + std::to_string(version) + "; this mcref reads version 1");
    DatasetHeader& h = header_;
    h.mcref_version = h5::read_string_attr(root, "mcref_version");
    h.git_commit = h5::read_string_attr(root, "git_commit");
    if (h5::has_attr(root, "sim_fingerprint")) h.sim_fingerprint = h5::read_string_attr(root, "sim_fingerprint");
    h.seed = static_cast<std::uint64_t>(h5::read_int_attr(root, "seed"));
    h.entries = h5::read_int_attr(root, "entries");
    h.shard = h5::read_string_attr(root, "shard");
    h.compression = static_cast<int>(h5::read_int_attr(root, "compression"));
    h.dataset_config = h5::read_string_attr(root, "dataset_config");
    h.experiment_config = h5::read_string_attr(root, "experiment_config");
    h.experiment_file = h5::read_string_attr(root, "experiment_file");
    if (h5::has_attr(root, "storage")) {
      const std::string storage = h5::read_string_attr(root, "storage");
      if (storage != "lean" && storage != "sums")
        throw ConfigError(path, "storage", "is \"" + storage + "\"; this mcref knows \"lean\" and \"sums\" (or none: full)");
      h.lean = storage == "lean";
      h.sums = storage == "sums";
    }
    h5::Handle p = h5::open_group(file_, "parameters");
    h.columns = h5::read_strings(p, "names");
    h5::Handle labels = h5::open_group(p, "labels");
    for (const std::string& column : h5::list_links(labels)) h.labels[column] = h5::read_strings(labels, column);
    indices_ = h5::read_int64s(p, "index");
    for (std::int64_t s : h5::read_int64s(p, "seed")) seeds_.push_back(static_cast<std::uint64_t>(s));
    assignments_ = h5::read_strings(p, "assignments");
    values_ = h5::read_doubles(p, "values");
    if (seeds_.size() != indices_.size() || assignments_.size() != indices_.size() ||
        values_.size() != indices_.size() * h.columns.size())
      throw std::runtime_error("the parameter table's shapes disagree");
    for (std::size_t i = 1; i < indices_.size(); ++i)
      if (indices_[i] <= indices_[i - 1]) throw std::runtime_error("entry indices are not increasing");
  } catch (const ConfigError&) {
    H5Fclose(file_);
    throw;
  } catch (const std::exception& e) {
    H5Fclose(file_);
    throw ConfigError(path, "", std::string("damaged mcref dataset file: ") + e.what());
  }
}

DatasetReader::~DatasetReader() {
  if (file_ >= 0) H5Fclose(file_);
}

DatasetEntry DatasetReader::entry(std::int64_t index) const {
  if (header_.lean)
    throw ConfigError(path_, "storage", "is a lean dataset (float32 value and stderr, no sums): its entries cannot be merged or resumed; use the full files");
  const auto it = std::lower_bound(indices_.begin(), indices_.end(), index);
  if (it == indices_.end() || *it != index)
    throw ConfigError(path_, "", "holds no entry " + std::to_string(index));
  const std::size_t row = static_cast<std::size_t>(it - indices_.begin());
  DatasetEntry e;
  e.index = index;
  e.seed = seeds_[row];
  e.assignments = assignments_[row];
  const std::size_t cols = header_.columns.size();
  e.parameters.assign(values_.begin() + static_cast<std::ptrdiff_t>(row * cols),
                      values_.begin() + static_cast<std::ptrdiff_t>((row + 1) * cols));
  try {
    h5::Handle g = h5::open_group(file_, "entries/" + std::to_string(index));
    e.config = h5::read_string_attr(g, "config");
    for (const std::string& name : h5::list_links(g)) e.tables.push_back(read_table_group(g, name));
  } catch (const std::exception& ex) {
    throw ConfigError(path_, "", "damaged entry " + std::to_string(index) + ": " + ex.what());
  }
  return e;
}

}  // namespace mcref
