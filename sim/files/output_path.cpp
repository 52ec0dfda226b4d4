#include "sim/files/output_path.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "sim/experiment/config_error.h"

namespace mcref {

namespace fs = std::filesystem;

namespace {

fs::path resolved(const std::string& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? fs::absolute(p).lexically_normal() : r;
}

void check_writable_parent(const std::string& path, const std::string& flag) {
  const fs::path parent = fs::absolute(path).parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw ConfigError(path, flag, "the output's directory " + parent.string() + " does not exist (mcref creates no directories for it)");
  if (access(parent.c_str(), W_OK | X_OK) != 0)
    throw ConfigError(path, flag, "the output's directory " + parent.string() + " is not writable");
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool eq = fs::equivalent(a, b, ec);
    if (!ec) return eq;
  }
  return resolved(a) == resolved(b);
}

void check_output_file(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag) {
  if (path.empty()) throw ConfigError("command line", flag, "an output path is required");
  for (const std::string& in : inputs)
    if (same_file(path, in)) throw ConfigError(path, flag, "is the input " + in + "; choose another output");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ConfigError(path, flag, "is a directory; give a file name");
  if (fs::exists(path, ec) && access(path.c_str(), W_OK) != 0 && access(fs::absolute(path).parent_path().c_str(), W_OK) != 0)
    throw ConfigError(path, flag, "exists and cannot be replaced");
  check_writable_parent(path, flag);
}

void check_output_directory(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag) {
  if (path.empty()) throw ConfigError("command line", flag, "an output directory is required");
  std::error_code ec;
  if (fs::exists(path, ec)) {
    if (!fs::is_directory(path, ec)) throw ConfigError(path, flag, "exists and is not a directory; give a directory");
    if (access(path.c_str(), W_OK | X_OK) != 0) throw ConfigError(path, flag, "is not a writable directory");
  } else {
    check_writable_parent(path, flag);
  }
  for (const std::string& in : inputs)
    if (same_file(path, in)) throw ConfigError(path, flag, "is the input " + in + "; choose another output");
}

}  // namespace mcref
