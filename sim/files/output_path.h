#pragma once
// The rules every verb applies to its outputs before any work starts, so that
// a run never fails after the work for a reason it could have seen first:
//   - the parent directory must exist and be writable (no verb creates it);
//   - an output file must not be an existing directory;
//   - an output must not resolve to any input (links and ".." resolved).
// Violations are ConfigError naming the path and the flag.
#include <string>
#include <vector>

namespace mcref {

// An output file (-o FILE); `inputs` are every file the run reads.
void check_output_file(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag = "-o");
// An output directory (-o DIR): created if missing (its parent must exist), or
// an existing writable directory.
void check_output_directory(const std::string& path, const std::vector<std::string>& inputs,
                            const std::string& flag = "-o");
// True if a and b name the same file (both existing: same inode; otherwise the
// same canonical path).
bool same_file(const std::string& a, const std::string& b);

}  // namespace mcref
