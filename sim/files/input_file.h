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

// The line an input's content adds to a configuration's provenance text:
// "\n# <key> read from "<path>": bytes=<n> fnv1a64=<hex>\n" (a TOML comment).
std::string input_provenance(const std::string& key, const std::string& path, const std::string& bytes);

}  // namespace mcref
