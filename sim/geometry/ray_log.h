#pragma once
// An optional record of the rays a MicrograinField passes to rtcIntersect1,
// per thread. bench_micrograin_transport replays them through bare
// rtcIntersect1 to measure the walk's overhead over tracing the same rays.
// Off (one predictable branch per ray) unless a log is set for the thread.
#include <vector>

namespace mcref {

struct LoggedRay {
  float org[3], dir[3], tnear, tfar;
};

// The calling thread's log; nullptr (the default) turns logging off.
inline thread_local std::vector<LoggedRay>* t_ray_log = nullptr;

}  // namespace mcref
