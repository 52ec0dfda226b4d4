#pragma once
// Temporary files of the writers. Every output is written to
// <output>.tmp.<pid>, checked (stream state, flush, close), and only then
// renamed over <output>: a failed or interrupted write never leaves a
// half-written output and never replaces a good one.
//   - SIGINT, SIGTERM and SIGHUP remove the temporaries alive at that moment,
//     then end the process as the signal would have;
//   - a temporary left by a process that no longer runs (SIGKILL, power loss)
//     is removed by the next run writing the same output.
#include <string>

namespace mcref {

class TempFile {
 public:
  // Removes stale temporaries of `output`, then names this process's own.
  explicit TempFile(std::string output);
  ~TempFile();  // removes the temporary unless committed
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::string& path() const { return tmp_; }
  // Renames the temporary over the output (throws std::runtime_error naming it).
  void commit();

 private:
  std::string output_, tmp_;
  int slot_ = -1;  // in the signal handler's list
  bool committed_ = false;
};

// Writes `text` to `path` through a TempFile (std::runtime_error naming path on
// failure: write errors are not bad input, and the CLI exits 1 on them).
void write_text_file(const std::string& path, const std::string& text);

// Leaves SIGINT, SIGTERM and SIGHUP to the host process: no TempFile installs
// its handlers afterwards. For the Python module, whose interpreter handles them
// itself (SIGINT raises KeyboardInterrupt once the call returns, and the
// temporary of a write it interrupts is removed by the destructor; a temporary
// left by a process a signal ended is removed by the next write of that output).
void leave_signals_to_host();

// <output>.tmp.<pid> files whose process no longer runs, removed; returns how many.
int remove_stale_temps(const std::string& output);

// True if the file name `name` has the form of a temporary of the output file
// named `output_name` (<output_name>.tmp.<pid>; names only, no directories).
bool is_temp_name(const std::string& name, const std::string& output_name);

}  // namespace mcref
