#pragma once
// Reading an input text file (experiment, dataset, suite) whole, with the
// one-line errors the verbs print: missing, a directory, unreadable.
#include <string>

namespace mcref {

// `from_file` and `key` name where the path came from (empty: the command line).
std::string read_input_file(const std::string& path, const std::string& from_file = "", const std::string& key = "");

// A path given in `file`: as it is if absolute, else relative to the file's folder
// (to the working directory if `file` names none).
std::string path_beside(const std::string& file, const std::string& path);

// A file an experiment reads besides itself (geometry.density_vdb).
struct InputFile {
  std::string path;    // resolved
  std::string digest;  // of its content: "bytes=<n> fnv1a64=<hex>" (sim/hdf5/file_seal.h content_digest)
};

// The line an input adds to a configuration's provenance text, a TOML comment:
// "\n# <key> read from "<path>": <digest>\n" (`path` as the configuration gives it).
std::string input_provenance(const std::string& key, const std::string& path, const std::string& digest);

}  // namespace mcref
