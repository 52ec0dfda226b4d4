#include "sim/hdf5/table_file.h"

#include <hdf5.h>
#include <hdf5_hl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "mcref_commit.h"  // generated at build time
#include "mcref_sim_fingerprint.h"  // generated at build time
#include "sim/experiment/config_error.h"
#include "sim/files/temp_file.h"
#include "sim/hdf5/file_seal.h"
#include "sim/hdf5/h5_util.h"
#include "sim/hdf5/table_group.h"

namespace mcref {

namespace {

constexpr const char* kFormat = "mcref-tables";
constexpr int kFormatVersion = 1;

herr_t collect_group(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}

}  // namespace

const Table* TableFile::find(const std::string& name) const {
  for (const Table& t : tables)
    if (t.name == name) return &t;
  return nullptr;
}

const char* table_conventions() {
  return "z is the macro normal; directions point away from the surface; theta from z, phi from +x. "
         "Relative azimuth phi = phi_o - phi_i: 0 is back toward the light, pi the mirror side. "
         "Angles in radians. BRDF/BTDF values are f in 1/sr WITHOUT the cosine factor. "
         "Binned values are bin averages (see each table's description). "
         "value = sum / batches; stderr = sqrt((sum_sq/batches - value^2) * batches/(batches-1) / batches); "
         "one batch = one independent realization of the random geometry.";
}

std::string mcref_version() { return MCREF_VERSION; }
std::string mcref_git_commit() { return MCREF_GIT_COMMIT; }
std::string mcref_sim_fingerprint() { return MCREF_SIM_FINGERPRINT; }

Provenance make_provenance(const std::string& config_text, const std::string& source_file, std::uint64_t seed,
                           const std::string& command_line) {
  Provenance p;
  p.mcref_version = mcref_version();
  p.git_commit = mcref_git_commit();
  p.sim_fingerprint = mcref_sim_fingerprint();
  char buf[64];
  // SOURCE_DATE_EPOCH (the reproducible-builds convention) fixes the date, so
  // that two runs can be compared byte for byte.
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  const std::time_t now = epoch && *epoch ? static_cast<std::time_t>(std::strtoll(epoch, nullptr, 10)) : std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  p.created = buf;
  p.command_line = command_line;
  p.config = config_text;
  p.source_file = source_file;
  p.seed = seed;
  return p;
}

namespace {

// Names the file's layout cannot hold (tables made by hand, in Python): a
// table's group and an axis's datasets are named after them, beside the
// table's own datasets.
void check_names(const std::string& path, const TableFile& f) {
  // (A NUL would cut the name short in the file.)
  const auto usable = [](const std::string& n) {
    return !n.empty() && n != "." && n != ".." && n.find('/') == std::string::npos && n.find('\0') == std::string::npos;
  };
  std::set<std::string> tables;
  for (const Table& t : f.tables) {
    if (!usable(t.name)) throw ConfigError(path, "", "table name \"" + t.name + "\" must be non-empty, not . or .., and without '/'");
    if (!tables.insert(t.name).second) throw ConfigError(path, "", "two tables are named \"" + t.name + "\"");
    std::set<std::string> taken{"value", "stderr", "sum", "sum_sq", "bnds", "batch_values", "batch"};
    for (const Axis& a : t.axes)
      for (const std::string& n : {a.name, a.name + "_bounds", a.name + "_label"})
        if (!usable(a.name) || !taken.insert(n).second)
          throw ConfigError(path, "", "table \"" + t.name + "\": axis name \"" + a.name + "\" must be non-empty, without '/', "
                                      "not value, stderr, sum, sum_sq, bnds, batch_values or batch, and unlike the others and their _bounds and _label");
    // Notes under the layout's own attribute names were refused by HDF5 as "disk full?", or
    // made the file unreadable (storage).
    for (const auto& [key, value] : t.attributes)
      if (!usable(key) || reserved_table_attribute(key) || value.find('\0') != std::string::npos)
        throw ConfigError(path, "", "table \"" + t.name + "\": attribute \"" + key + "\" must be non-empty, without '/' or NUL, "
                                    "with a value without NUL, and not quantity, units, description, batches, axes or storage");
  }
}

}  // namespace

void write_table_file(const std::string& path, const TableFile& f) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  check_names(path, f);
  TempFile tmp(path);
  try {
    h5::Handle fcpl = h5::file_create_plist();
    h5::Handle file(H5Fcreate(tmp.path().c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw ConfigError(path, "", "cannot create the output file (is the directory writable?)");
    h5::Handle root = h5::open_group(file, "/");
    h5::write_string_attr(root, "mcref_format", kFormat);
    h5::write_int_attr(root, "format_version", kFormatVersion);
    h5::write_string_attr(root, "mcref_version", f.provenance.mcref_version);
    h5::write_string_attr(root, "git_commit", f.provenance.git_commit);
    h5::write_string_attr(root, "sim_fingerprint", f.provenance.sim_fingerprint);
    h5::write_string_attr(root, "created", f.provenance.created);
    h5::write_string_attr(root, "command_line", f.provenance.command_line);
    h5::write_int_attr(root, "seed", static_cast<std::int64_t>(f.provenance.seed));
    h5::write_string_attr(root, "config", f.provenance.config);
    h5::write_string_attr(root, "source_file", f.provenance.source_file);
    h5::write_string_attr(root, "conventions", table_conventions());
    for (const Table& t : f.tables) write_table_group(file, t, 0);
    h5::check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flushing");
    root.close();
    file.close("closing");
    seal_file(tmp.path());
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": writing failed (" + e.what() + "; disk full?)");
  }
  tmp.commit();
}

TableFile read_table_file(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (!std::filesystem::exists(path)) throw ConfigError(path, "", "no such file");
  check_seal(path);  // before HDF5 reads a byte of a damaged file
  if (H5Fis_hdf5(path.c_str()) <= 0) throw ConfigError(path, "", "not an HDF5 file");
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw ConfigError(path, "", "cannot open the HDF5 file");
  h5::Handle root = h5::open_group(file, "/");
  TableFile f;
  try {
    const std::string format = h5::has_attr(root, "mcref_format") ? h5::read_string_attr(root, "mcref_format") : "";
    if (format == "mcref-dataset")  // (a dataset's entries hold tables; its layout: README, "Reference datasets")
      throw ConfigError(path, "mcref_format", "is an mcref dataset file, not a table file; read its entries' tables "
                                              "with h5py (README, \"Reference datasets\")");
    if (format != kFormat)
      throw ConfigError(path, "mcref_format", "not an mcref table file (root attribute mcref_format != \"mcref-tables\")");
    const std::int64_t version = h5::read_int_attr(root, "format_version");
    if (version != kFormatVersion)
      throw ConfigError(path, "format_version", "is " + std::to_string(version) + "; this mcref reads version 1");
    f.provenance.mcref_version = h5::read_string_attr(root, "mcref_version");
    f.provenance.git_commit = h5::read_string_attr(root, "git_commit");
    if (h5::has_attr(root, "sim_fingerprint")) f.provenance.sim_fingerprint = h5::read_string_attr(root, "sim_fingerprint");
    f.provenance.created = h5::read_string_attr(root, "created");
    f.provenance.command_line = h5::read_string_attr(root, "command_line");
    f.provenance.seed = static_cast<std::uint64_t>(h5::read_int_attr(root, "seed"));
    f.provenance.config = h5::read_string_attr(root, "config");
    f.provenance.source_file = h5::read_string_attr(root, "source_file");
    std::vector<std::string> groups;
    H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_group, &groups);
    for (const std::string& g : groups) f.tables.push_back(read_table_group(file, g));
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(path, "", std::string("damaged mcref table file: ") + e.what());
  }
  return f;
}

}  // namespace mcref
