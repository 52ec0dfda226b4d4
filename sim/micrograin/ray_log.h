#pragma once
// An optional record of the rays a MicrograinField passes to rtcIntersect1,
// per thread. bench_micrograin_transport replays them (MicrograinField::
// embree_intersect) to measure the walk's overhead over tracing the same rays.
// Off (one predictable branch per ray) unless a log is set for the thread.
#include <cstdint>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

struct LoggedRay {
  float org[3], dir[3], tnear, tfar;
  // A ray leaving grain `leaving` from the exact unit-space point `origin` on
  // it: Embree's hits on that grain are rejected by a context filter.
  // MicrograinField::kNoGrain: no filter (`origin` unused).
  Vec3 origin;
  std::uint32_t leaving;
};

// The calling thread's log; nullptr (the default) turns logging off.
inline thread_local std::vector<LoggedRay>* t_ray_log = nullptr;

}  // namespace mcref
