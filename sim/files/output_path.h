#pragma once
// The rules every verb applies to its outputs before any work starts, so that
// a run never fails after the work for a reason it could have seen first:
//   - the parent directory must exist and be writable (no verb creates it);
//   - an existing output file must be a regular file (or a symbolic link, see
//     below): a directory, FIFO, device or socket is refused, since the new
//     file is renamed over the output and would replace it;
//   - a symbolic link given as an output is itself replaced by the new file;
//     the file it points to is left as it was;
//   - the temporary name <output>.tmp.<pid> must fit the file system's name
//     limit (NAME_MAX);
//   - an output must not resolve to any input (links and ".." resolved), no
//     input may be named as the output's temporary (<output>.tmp.<pid>: a stale
//     one is removed), and no input may lie in a directory the run writes into
//     (check_inputs_outside).
// Violations are ConfigError naming the path and the flag.
#include <string>
#include <vector>

namespace mcref {

// An output file (-o FILE); `inputs` are every file the run reads.
void check_output_file(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag = "-o");
// The same without the parent directory's checks: a file in a directory the run
// creates (validate's OUTDIR/results.json).
void check_replaceable_file(const std::string& path, const std::vector<std::string>& inputs,
                            const std::string& flag = "-o");
// An output directory (-o DIR): created if missing (its parent must exist), or
// an existing writable directory.
void check_output_directory(const std::string& path, const std::vector<std::string>& inputs,
                            const std::string& flag = "-o");
// Refuses an input inside `dir`, a directory the run writes into for `output`
// (the input named, or the file it links to): the run could replace or remove it.
void check_inputs_outside(const std::string& dir, const std::vector<std::string>& inputs, const std::string& output);
// True if a and b name the same file (both existing: same inode; otherwise the
// same canonical path).
bool same_file(const std::string& a, const std::string& b);

}  // namespace mcref
