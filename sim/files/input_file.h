#pragma once
// Reading an input text file (experiment, dataset, suite) whole, with the
// one-line errors the verbs print: missing, a directory, unreadable.
#include <string>

namespace mcref {

// `from_file` and `key` name where the path came from (empty: the command line).
std::string read_input_file(const std::string& path, const std::string& from_file = "", const std::string& key = "");

}  // namespace mcref
