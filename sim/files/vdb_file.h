#pragma once
// Writing OpenVDB files safely: the grids go to a temporary file through a
// checked stream (OpenVDB's own io::File::write never checks its stream, so a
// full disk gave a truncated file and success); only a complete, closed file
// is renamed over the output.
#include <openvdb/openvdb.h>

#include <string>

namespace mcref {

// Throws std::runtime_error naming `path` if anything fails; `path` is then untouched.
void write_vdb_file(const std::string& path, const openvdb::GridCPtrVec& grids);

}  // namespace mcref
