#include "sim/io/table_file.h"

#include <hdf5.h>
#include <hdf5_hl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include "mcref_commit.h"  // generated at build time
#include "sim/config/config_error.h"

namespace mcref {

namespace {

constexpr const char* kFormat = "mcref-tables";
constexpr int kFormatVersion = 1;

// Closes an HDF5 handle at scope exit.
struct H5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  H5Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~H5Handle() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5 error while " + what);
}

void write_string_attr(hid_t obj, const std::string& name, const std::string& value) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_size(type, H5T_VARIABLE), "sizing a string");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "setting UTF-8");
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle attr(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const char* p = value.c_str();
  check(H5Awrite(attr, type, &p), "writing attribute " + name);
}

void write_int_attr(hid_t obj, const std::string& name, std::int64_t value) {
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_INT64, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(H5Awrite(attr, H5T_NATIVE_INT64, &value), "writing attribute " + name);
}

bool has_attr(hid_t obj, const std::string& name) { return H5Aexists(obj, name.c_str()) > 0; }

std::string read_string_attr(hid_t obj, const std::string& name) {
  H5Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (attr < 0) throw std::runtime_error("missing attribute " + name);
  H5Handle ftype(H5Aget_type(attr), H5Tclose);
  if (H5Tget_class(ftype) != H5T_STRING) throw std::runtime_error("attribute " + name + " is not a string");
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_cset(type, H5Tget_cset(ftype)), "matching the character set");
  if (H5Tis_variable_str(ftype) > 0) {
    check(H5Tset_size(type, H5T_VARIABLE), "sizing a string");
    char* p = nullptr;
    check(H5Aread(attr, type, &p), "reading attribute " + name);
    std::string s = p ? p : "";
    H5free_memory(p);
    return s;
  }
  const std::size_t n = H5Tget_size(ftype);
  check(H5Tset_size(type, n), "sizing a string");
  std::string s(n, '\0');
  check(H5Aread(attr, type, s.data()), "reading attribute " + name);
  s.resize(std::strlen(s.c_str()));
  return s;
}

std::int64_t read_int_attr(hid_t obj, const std::string& name) {
  H5Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (attr < 0) throw std::runtime_error("missing attribute " + name);
  std::int64_t v = 0;
  check(H5Aread(attr, H5T_NATIVE_INT64, &v), "reading attribute " + name);
  return v;
}

hid_t write_dataset(hid_t group, const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data) {
  H5Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  const hid_t ds = H5Dcreate2(group, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds < 0) throw std::runtime_error("HDF5 error creating dataset " + name);
  check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "writing dataset " + name);
  return ds;
}

std::vector<double> read_dataset(hid_t group, const std::string& name) {
  H5Handle ds(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) throw std::runtime_error("missing dataset " + name);
  H5Handle space(H5Dget_space(ds), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> v(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "reading " + name);
  return v;
}

const std::set<std::string> kReservedTableAttrs{"quantity", "units", "description", "batches", "axes"};

void write_table(hid_t file, const Table& t) {
  H5Handle group(H5Gcreate2(file, t.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (group < 0) throw std::runtime_error("cannot create group " + t.name);
  write_string_attr(group, "quantity", t.quantity);
  write_string_attr(group, "units", t.units);
  write_string_attr(group, "description", t.description);
  write_int_attr(group, "batches", t.batches);
  std::string axes;
  for (const Axis& a : t.axes) axes += (axes.empty() ? "" : ",") + a.name;
  write_string_attr(group, "axes", axes);
  for (const auto& [k, v] : t.attributes) write_string_attr(group, k, v);
  std::vector<hsize_t> dims;
  for (std::size_t n : t.shape()) dims.push_back(n);
  std::vector<hid_t> data{write_dataset(group, "value", dims, t.values()),
                          write_dataset(group, "stderr", dims, t.stderrs()),
                          write_dataset(group, "sum", dims, t.sum), write_dataset(group, "sum_sq", dims, t.sum_sq)};
  for (std::size_t d = 0; d < t.axes.size(); ++d) {
    const Axis& a = t.axes[d];
    std::vector<double> pts(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) pts[i] = a.centre(i);
    H5Handle scale(write_dataset(group, a.name, {a.size()}, pts), H5Dclose);
    write_string_attr(scale, "unit", a.unit);
    write_string_attr(scale, "kind", a.kind == Axis::Kind::Bins ? "bin centres" : "points");
    check(H5DSset_scale(scale, a.name.c_str()), "making a dimension scale");
    for (hid_t ds : data) check(H5DSattach_scale(ds, scale, static_cast<unsigned>(d)), "attaching a scale");
    if (a.kind == Axis::Kind::Bins) {
      H5Handle edges(write_dataset(group, a.name + "_edges", {a.values.size()}, a.values), H5Dclose);
      write_string_attr(edges, "unit", a.unit);
    }
  }
  for (hid_t ds : data) H5Dclose(ds);
}

Table read_table(hid_t file, const std::string& name) {
  H5Handle group(H5Gopen2(file, name.c_str(), H5P_DEFAULT), H5Gclose);
  std::vector<Axis> axes;
  std::stringstream ss(read_string_attr(group, "axes"));
  for (std::string a; std::getline(ss, a, ',');) {
    H5Handle scale(H5Dopen2(group, a.c_str(), H5P_DEFAULT), H5Dclose);
    if (scale < 0) throw std::runtime_error("missing axis " + a);
    const std::string unit = read_string_attr(scale, "unit");
    if (H5Lexists(group, (a + "_edges").c_str(), H5P_DEFAULT) > 0)
      axes.push_back(Axis::bins(a, unit, read_dataset(group, a + "_edges")));
    else
      axes.push_back(Axis::points(a, unit, read_dataset(group, a)));
  }
  Table t(name, read_string_attr(group, "quantity"), axes);
  t.units = read_string_attr(group, "units");
  t.description = read_string_attr(group, "description");
  t.batches = read_int_attr(group, "batches");
  t.sum = read_dataset(group, "sum");
  t.sum_sq = read_dataset(group, "sum_sq");
  if (t.sum.size() != t.cells() || t.sum_sq.size() != t.cells()) throw std::runtime_error("table shape mismatch");
  const int n = H5Aget_num_attrs(group);
  for (int i = 0; i < n; ++i) {
    H5Handle attr(H5Aopen_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    char buf[256] = {0};
    H5Aget_name(attr, sizeof buf, buf);
    if (!kReservedTableAttrs.count(buf)) t.attributes[buf] = read_string_attr(group, buf);
  }
  return t;
}

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

Provenance make_provenance(const std::string& config_text, const std::string& source_file, std::uint64_t seed,
                           const std::string& command_line) {
  Provenance p;
  p.mcref_version = mcref_version();
  p.git_commit = mcref_git_commit();
  char buf[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  p.created = buf;
  p.command_line = command_line;
  p.config = config_text;
  p.source_file = source_file;
  p.seed = seed;
  return p;
}

void write_table_file(const std::string& path, const TableFile& f) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string tmp = path + ".tmp." + std::to_string(getpid());
  try {
    {
      H5Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
      if (file < 0) throw ConfigError(path, "", "cannot create the output file (is the directory writable?)");
      H5Handle root(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose);
      write_string_attr(root, "mcref_format", kFormat);
      write_int_attr(root, "format_version", kFormatVersion);
      write_string_attr(root, "mcref_version", f.provenance.mcref_version);
      write_string_attr(root, "git_commit", f.provenance.git_commit);
      write_string_attr(root, "created", f.provenance.created);
      write_string_attr(root, "command_line", f.provenance.command_line);
      write_int_attr(root, "seed", static_cast<std::int64_t>(f.provenance.seed));
      write_string_attr(root, "config", f.provenance.config);
      write_string_attr(root, "source_file", f.provenance.source_file);
      write_string_attr(root, "conventions", table_conventions());
      for (const Table& t : f.tables) write_table(file, t);
      check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flushing");
    }
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

TableFile read_table_file(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (!std::filesystem::exists(path)) throw ConfigError(path, "", "no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw ConfigError(path, "", "not an HDF5 file");
  H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) throw ConfigError(path, "", "cannot open the HDF5 file");
  H5Handle root(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose);
  if (!has_attr(root, "mcref_format") || read_string_attr(root, "mcref_format") != kFormat)
    throw ConfigError(path, "mcref_format", "not an mcref table file (root attribute mcref_format != \"mcref-tables\")");
  TableFile f;
  try {
    const std::int64_t version = read_int_attr(root, "format_version");
    if (version != kFormatVersion)
      throw ConfigError(path, "format_version", "is " + std::to_string(version) + "; this mcref reads version 1");
    f.provenance.mcref_version = read_string_attr(root, "mcref_version");
    f.provenance.git_commit = read_string_attr(root, "git_commit");
    f.provenance.created = read_string_attr(root, "created");
    f.provenance.command_line = read_string_attr(root, "command_line");
    f.provenance.seed = static_cast<std::uint64_t>(read_int_attr(root, "seed"));
    f.provenance.config = read_string_attr(root, "config");
    f.provenance.source_file = read_string_attr(root, "source_file");
    std::vector<std::string> groups;
    H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_group, &groups);
    for (const std::string& g : groups) f.tables.push_back(read_table(file, g));
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(path, "", std::string("damaged mcref table file: ") + e.what());
  }
  return f;
}

}  // namespace mcref
