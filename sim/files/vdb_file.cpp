#include "sim/files/vdb_file.h"

#include <openvdb/io/Stream.h>

#include <fstream>
#include <stdexcept>

#include "sim/files/temp_file.h"

namespace mcref {

void write_vdb_file(const std::string& path, const openvdb::GridCPtrVec& grids) {
  openvdb::initialize();
  TempFile tmp(path);
  {
    std::ofstream out(tmp.path(), std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot create the output file");
    try {
      openvdb::io::Stream(out).write(grids);
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ": writing the grids failed: " + e.what());
    }
    out.flush();
    if (!out) throw std::runtime_error(path + ": writing the grids failed (disk full?)");
    out.close();
    if (out.fail()) throw std::runtime_error(path + ": closing the file failed (disk full?)");
  }
  tmp.commit();
}

}  // namespace mcref
