#pragma once
// Small HDF5 helpers for mcref files (tables and datasets). Every object is created
// without time tracking (H5Pset_obj_track_times false), so the bytes of a
// file depend only on what is written and in which order: two runs that write
// the same content in the same order give bit-identical files.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace mcref::h5 {

// Closes an HDF5 handle at scope exit.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now and throws std::runtime_error naming `what` if that fails (a
  // file's close writes its last metadata: a full disk shows here). The id is
  // given up either way, so nothing closes it twice.
  void close(const std::string& what = "closing");

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void check(herr_t status, const std::string& what);  // throws std::runtime_error

// Creation property lists without time tracking.
Handle file_create_plist();
Handle group_create_plist();
Handle dataset_create_plist(const std::vector<hsize_t>& dims, int compression);

Handle create_group(hid_t parent, const std::string& name);
Handle open_group(hid_t parent, const std::string& name);  // throws if missing
bool exists(hid_t parent, const std::string& name);

void write_string_attr(hid_t obj, const std::string& name, const std::string& value);
void write_int_attr(hid_t obj, const std::string& name, std::int64_t value);
bool has_attr(hid_t obj, const std::string& name);
std::string read_string_attr(hid_t obj, const std::string& name);
std::int64_t read_int_attr(hid_t obj, const std::string& name);

// float64 / int64 / variable-length UTF-8 string datasets; `compression` is a
// gzip level (0: contiguous, uncompressed).
Handle write_doubles(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims,
                     const std::vector<double>& data, int compression = 0);
// The same, stored as float32 (rounded to nearest); read back with read_doubles.
Handle write_floats(hid_t parent, const std::string& name, const std::vector<hsize_t>& dims,
                    const std::vector<double>& data, int compression = 0);
void write_int64s(hid_t parent, const std::string& name, const std::vector<std::int64_t>& data);
Handle write_strings(hid_t parent, const std::string& name, const std::vector<std::string>& data);
std::vector<double> read_doubles(hid_t parent, const std::string& name);
std::vector<std::int64_t> read_int64s(hid_t parent, const std::string& name);
std::vector<std::string> read_strings(hid_t parent, const std::string& name);

// Names of the links in a group, in name order.
std::vector<std::string> list_links(hid_t group);

}  // namespace mcref::h5
