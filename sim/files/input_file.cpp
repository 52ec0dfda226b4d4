#include "sim/files/input_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "sim/experiment/config_error.h"

namespace mcref {

std::string read_input_file(const std::string& path, const std::string& from_file, const std::string& key) {
  const std::string where = from_file.empty() ? path : from_file;
  const std::string what = from_file.empty() ? "" : "'" + path + "' ";
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ConfigError(where, key, what + "no such file");
  if (std::filesystem::is_directory(path, ec)) throw ConfigError(where, key, what + "is a directory, not a file");
  // (A FIFO or a device would block the read, or never end.)
  if (!std::filesystem::is_regular_file(path, ec)) throw ConfigError(where, key, what + "is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(where, key, what + "cannot be read");
  std::stringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw ConfigError(where, key, what + "cannot be read");
  return buf.str();
}

std::string path_beside(const std::string& file, const std::string& path) {
  const std::filesystem::path given(path);
  if (given.is_absolute()) return path;
  return (std::filesystem::path(file).parent_path() / given).lexically_normal().string();
}

std::string input_provenance(const std::string& key, const std::string& path, const std::string& digest) {
  return "\n# " + key + " read from \"" + path + "\": " + digest + "\n";
}

}  // namespace mcref
