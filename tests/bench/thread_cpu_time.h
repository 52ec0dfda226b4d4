#pragma once
// CPU time of the calling thread in seconds: on a machine shared with other
// jobs, the time a single-threaded benchmark loop really ran, unlike wall time.
#include <time.h>

namespace mcref::bench {

inline double thread_cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace mcref::bench
