#include "sim/hdf5/h5_util.h"

#include <cstring>
#include <stdexcept>

#include "sim/hdf5/file_seal.h"

namespace mcref::h5 {

void Handle::close(const std::string& what) {
  if (id_ < 0) return;
  const herr_t status = close_(id_);
  id_ = -1;
  check(status, what);
}

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5 error while " + what);
}

Handle file_create_plist() {
  Handle p(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  check(H5Pset_obj_track_times(p, false), "disabling time tracking");
  check(H5Pset_userblock(p, kSealBlockBytes), "reserving the seal's user block");
  return p;
}

Handle group_create_plist() {
  Handle p(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  check(H5Pset_obj_track_times(p, false), "disabling time tracking");
  return p;
}

Handle dataset_create_plist(const std::vector<hsize_t>& dims, int compression) {
  Handle p(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  check(H5Pset_obj_track_times(p, false), "disabling time tracking");
  std::size_t n = 1;
  for (hsize_t d : dims) n *= d;
  if (compression > 0 && n > 0 && !dims.empty()) {
    check(H5Pset_chunk(p, static_cast<int>(dims.size()), dims.data()), "chunking");
    check(H5Pset_shuffle(p), "setting the shuffle filter");
    check(H5Pset_deflate(p, static_cast<unsigned>(compression)), "setting gzip");
  }
  return p;
}

Handle create_group(hid_t parent, const std::string& name) {
  Handle gcpl = group_create_plist();
  Handle g(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw std::runtime_error("HDF5 error creating group " + name);
  return g;
}

Handle open_group(hid_t parent, const std::string& name) {
  Handle g(H5Gopen2(parent, name.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw std::runtime_error("missing group " + name);
  return g;
}

bool exists(hid_t parent, const std::string& name) { return H5Lexists(parent, name.c_str(), H5P_DEFAULT) > 0; }

namespace {
Handle string_type() {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_size(type, H5T_VARIABLE), "sizing a string");
  check(H5Tset_cset(type, H5T_CSET_UTF8), "setting UTF-8");
  return type;
}
}  // namespace

void write_string_attr(hid_t obj, const std::string& name, const std::string& value) {
  Handle type = string_type();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const char* p = value.c_str();
  check(H5Awrite(attr, type, &p), "writing attribute " + name);
}

void write_int_attr(hid_t obj, const std::string& name, std::int64_t value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_INT64, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(H5Awrite(attr, H5T_NATIVE_INT64, &value), "writing attribute " + name);
}

bool has_attr(hid_t obj, const std::string& name) { return H5Aexists(obj, name.c_str()) > 0; }

std::string read_string_attr(hid_t obj, const std::string& name) {
  Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) throw std::runtime_error("missing attribute " + name);
  Handle ftype(H5Aget_type(attr), H5Tclose);
  if (H5Tget_class(ftype) != H5T_STRING || H5Tis_variable_str(ftype) <= 0)
    throw std::runtime_error("attribute " + name + " is not a variable-length string");
  Handle type = string_type();
  char* p = nullptr;
  check(H5Aread(attr, type, &p), "reading attribute " + name);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

std::int64_t read_int_attr(hid_t obj, const std::string& name) {
  Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) throw std::runtime_error("missing attribute " + name);
  std::int64_t v = 0;
  check(H5Aread(attr, H5T_NATIVE_INT64, &v), "reading attribute " + name);
  return v;
}

Handle write_doubles(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims,
                     const std::vector<double>& data, int compression) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl = dataset_create_plist(dims, compression);
  Handle ds(H5Dcreate2(parent, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 error creating dataset " + name);
  if (!data.empty())
    check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "writing dataset " + name);
  return ds;
}

Handle write_floats(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims,
                    const std::vector<double>& data, int compression) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl = dataset_create_plist(dims, compression);
  Handle ds(H5Dcreate2(parent, name.c_str(), H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 error creating dataset " + name);
  std::vector<float> f(data.begin(), data.end());
  if (!f.empty())
    check(H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, f.data()), "writing dataset " + name);
  return ds;
}

void write_int64s(hid_t parent, const std::string& name, const std::vector<std::int64_t>& data) {
  const hsize_t n = data.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Handle dcpl = dataset_create_plist({n}, 0);
  Handle ds(H5Dcreate2(parent, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 error creating dataset " + name);
  if (n) check(H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "writing " + name);
}

Handle write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& data) {
  const hsize_t n = data.size();
  Handle type = string_type();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Handle dcpl = dataset_create_plist({n}, 0);
  Handle ds(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 error creating dataset " + name);
  std::vector<const char*> p;
  for (const std::string& s : data) p.push_back(s.c_str());
  if (n) check(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "writing " + name);
  return ds;
}

namespace {
Handle open_dataset(hid_t parent, const std::string& name, hssize_t& n) {
  Handle ds(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("missing dataset " + name);
  Handle space(H5Dget_space(ds), H5Sclose);
  n = H5Sget_simple_extent_npoints(space);
  if (n < 0) throw std::runtime_error("bad dataset " + name);
  return ds;
}
}  // namespace

std::vector<double> read_doubles(hid_t parent, const std::string& name) {
  hssize_t n = 0;
  Handle ds = open_dataset(parent, name, n);
  std::vector<double> v(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "reading " + name);
  return v;
}

std::vector<std::int64_t> read_int64s(hid_t parent, const std::string& name) {
  hssize_t n = 0;
  Handle ds = open_dataset(parent, name, n);
  std::vector<std::int64_t> v(static_cast<std::size_t>(n));
  if (n > 0) check(H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "reading " + name);
  return v;
}

std::vector<std::string> read_strings(hid_t parent, const std::string& name) {
  hssize_t n = 0;
  Handle ds = open_dataset(parent, name, n);
  Handle type = string_type();
  std::vector<char*> p(static_cast<std::size_t>(n), nullptr);
  if (n > 0) check(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "reading " + name);
  std::vector<std::string> v;
  for (char* c : p) {
    v.push_back(c ? c : "");
    H5free_memory(c);
  }
  return v;
}

namespace {
herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}
}  // namespace

std::vector<std::string> list_links(hid_t group) {
  std::vector<std::string> names;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_link, &names), "listing a group");
  return names;
}

}  // namespace mcref::h5
