#pragma once
// A progress line with an ETA on a terminal; silent when --quiet, when stderr
// is not a terminal, or in CI (CI env variable set). Under MPI, callers draw
// it on rank 0 only, over the whole job, and as a log: one plain line a minute
// (mpirun gives every rank a terminal even when its own output goes to a
// file, so a redrawn line would fill a job's log). One summary line at the
// end is printed by the caller.
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

namespace mcref {

// Thrown by Progress::advance once its stop flag is set (another thread asked
// the run to stop: the Python module, on Ctrl-C).
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

class Progress {
 public:
  Progress(std::string label, double total_work, bool quiet);
  // Adds done work and redraws (at most ~5 times a second); throws Cancelled
  // if the stop flag is set.
  void advance(double work);
  void stop_when(const std::atomic<bool>* flag) { stop_ = flag; }
  // Clears the line.
  void finish();
  double elapsed_seconds() const;
  static bool interactive(bool quiet);

 private:
  std::string label_;
  double total_, done_ = 0;
  bool enabled_;
  bool log_;  // under MPI: a plain line a minute
  const std::atomic<bool>* stop_ = nullptr;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace mcref
