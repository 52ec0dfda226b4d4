#pragma once
// The order in which a batch of rays with one direction is traced in packets:
// origins sorted by the Morton index of their cell in a grid over the tile,
// so that the rays of a packet start close together and cross the same BVH
// nodes. A counting sort: stable, and the same for any thread count.
#include <cstdint>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

// Origins per grid cell for the micrograin estimators' batches of 4096 rays
// in packets of 16 (bench_micrograin: 1 and 16 were slower).
constexpr std::size_t kPacketOriginsPerCell = 4;

// order[0..n) := the indices 0..n-1 of `origins` (unit space, x in
// [0, side_x), y in [0, side_y)) in Morton order of a 2^k x 2^k grid with
// about `per_cell` origins per cell, and sorted[i] := origins[order[i]] (read
// in order by the tracer, rather than gathered). `cells` is scratch.
void packet_order(const Vec3* origins, std::size_t n, double side_x, double side_y, std::size_t per_cell,
                  std::vector<std::uint32_t>& order, std::vector<Vec3>& sorted, std::vector<std::uint32_t>& cells);

}  // namespace mcref
