#include "sim/files/output_path.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "sim/experiment/config_error.h"
#include "sim/files/temp_file.h"

namespace mcref {

namespace fs = std::filesystem;

namespace {

fs::path resolved(const std::string& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? fs::absolute(p).lexically_normal() : r;
}

// The path as named: its directory resolved, its last component kept (a link stays a link).
fs::path resolved_parent(const std::string& p) {
  const fs::path a = fs::absolute(p).lexically_normal();
  return a.has_filename() ? resolved(a.parent_path().string()) / a.filename() : resolved(p);
}

// True if p lies strictly below dir (both absolute and normal).
bool inside(const fs::path& p, const fs::path& dir) {
  auto x = p.begin();
  for (const fs::path& d : dir) {
    if (d.empty()) continue;  // a trailing separator
    if (x == p.end() || *x != d) return false;
    ++x;
  }
  return x != p.end() && !x->empty();
}

void check_writable_parent(const std::string& path, const std::string& flag) {
  const fs::path parent = fs::absolute(path).parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw ConfigError(path, flag, "the output's directory " + parent.string() + " does not exist (mcref creates no directories for it)");
  if (access(parent.c_str(), W_OK | X_OK) != 0)
    throw ConfigError(path, flag, "the output's directory " + parent.string() + " is not writable");
}

// What an existing path is if the new file must not be renamed over it ("" if it may).
std::string special_kind(const std::string& path) {
  std::error_code ec;
  switch (fs::symlink_status(path, ec).type()) {
    case fs::file_type::fifo: return "a FIFO (named pipe)";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::unknown: return "not a regular file";
    default: return "";  // none, regular, symlink, directory (refused apart)
  }
}

// <name>.tmp.<pid> within the name limit of the file system the output goes to
// (asked of its nearest existing directory).
void check_temp_name_fits(const std::string& path, const std::string& flag) {
  const fs::path abs = fs::absolute(path).lexically_normal();
  const std::string tmp = abs.filename().string() + ".tmp." + std::to_string(getpid());
  fs::path dir = abs.parent_path();
  std::error_code ec;
  while (!fs::is_directory(dir, ec) && dir.has_relative_path()) dir = dir.parent_path();
  const long max = pathconf(dir.c_str(), _PC_NAME_MAX);
  if (max > 0 && tmp.size() > static_cast<std::size_t>(max))
    throw ConfigError(path, flag, "the file name is too long: its temporary name " + tmp + " would have " +
                                      std::to_string(tmp.size()) + " characters, more than the " + std::to_string(max) +
                                      " the file system allows; choose a shorter name");
}

// Refuses an input named as a temporary of `path` (<output>.tmp.<pid>, the
// input itself or the file it links to): TempFile removes those whose process
// no longer runs, taking them for what a killed run left.
void check_no_input_named_as_temp(const std::string& path, const std::vector<std::string>& inputs,
                                  const std::string& flag) {
  const fs::path out = resolved_parent(path);
  for (const std::string& in : inputs)
    for (const fs::path& p : {resolved_parent(in), resolved(in)})
      if (p.parent_path() == out.parent_path() && is_temp_name(p.filename().string(), out.filename().string()))
        throw ConfigError(path, flag, "the input " + in + " is named as this output's temporary (" +
                                          out.filename().string() + ".tmp.<pid>), which a run removes once its " +
                                          "process has ended; rename the input or choose another output");
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

void check_replaceable_file(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag) {
  if (path.empty()) throw ConfigError("command line", flag, "an output path is required");
  for (const std::string& in : inputs)
    if (same_file(path, in)) throw ConfigError(path, flag, "is the input " + in + "; choose another output");
  check_no_input_named_as_temp(path, inputs, flag);
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ConfigError(path, flag, "is a directory; give a file name");
  const std::string kind = special_kind(path);
  if (!kind.empty())
    throw ConfigError(path, flag, "exists and is " + kind + ", not a regular file (writing would replace it with one); give another name");
  if (fs::exists(path, ec) && access(path.c_str(), W_OK) != 0 && access(fs::absolute(path).parent_path().c_str(), W_OK) != 0)
    throw ConfigError(path, flag, "exists and cannot be replaced");
  check_temp_name_fits(path, flag);
}

void check_output_file(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag) {
  check_replaceable_file(path, inputs, flag);
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

void check_inputs_outside(const std::string& dir, const std::vector<std::string>& inputs, const std::string& output) {
  const fs::path d = resolved(dir);
  for (const std::string& in : inputs)
    if (inside(resolved(in), d) || inside(resolved_parent(in), d))
      throw ConfigError(in, "", "is inside " + dir + ", where " + output +
                                    " replaces and removes files; move the input or choose another output");
}

}  // namespace mcref
