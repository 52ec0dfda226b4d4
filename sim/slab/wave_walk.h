#pragma once
// The slab walk of sim/slab/walk.h, data-parallel (a wavefront walk): a chunk's
// paths run kWaveLanes at a time in structure-of-arrays form, one scattering
// event per lane and step. The free flight and the phase-function event of
// every lane are each one loop the compiler vectorises (built for AVX-512,
// AVX2 and baseline x86-64, chosen at run time, the same bits on each); the
// substrate bounces, the tally and the refill of lanes whose path ended are
// scalar. Same physics, settings and tally as walk(), its estimators too (the
// next-event tallies in the scalar pass, sim/slab/next_event.h, with the
// weight before the roulette, as walk()'s); its
// own random streams (one xoshiro256** per lane, seeded from the chunk's
// generator; a next-event tally's draws from a generator seeded by its lane's
// stream), so tables agree with walk()'s within statistics, and are
// bit-identical for any thread count like walk()'s.
//
// Covers stacks of up to 4 layers of one phase function (SGGX surface and
// fibre flakes mix; or Henyey-Greenstein, isotropic, Lambert sphere) over any
// substrate. Each lane holds its layer's index and reads that layer's
// parameters by selects; a path crosses an inner face in the scalar pass (the
// flight ends there and the next one starts afresh: exact, the exponential
// being memoryless). Layers are homogeneous, or OpenVDB grids whose SGGX
// matrix is the same throughout each layer (any density). Where every layer's
// density varies in depth only (every stack a TOML describes), flights are
// exact, by inverting the optical depth as the scalar walk does
// (sim/slab/depth_profile.h), in the vector stage. Otherwise: delta tracking
// (Woodcock 1965) against the layer's largest cell majorant, a tentative
// collision decided by its cell's bounds (sim/slab/majorant_grid.h) and, where
// they leave it open, by the voxels in the scalar code; a lane tracks its
// lateral position in the tile.
#include <cstdint>
#include <string>

#include "sim/slab/medium.h"
#include "sim/slab/walk.h"

namespace mcref::volume {

inline constexpr int kWaveLanes = 256;

// "" if wave_walk() can run this medium, else why not.
std::string wave_walk_unsupported(const SlabGeometry& geometry);

// `count` paths entering the top face along -wi, tallied into `out` as
// walk() does; the lanes' streams are seeded from `rng`. Returns the number
// of scattering events.
std::uint64_t wave_walk(const SlabMedium& medium, const WalkSettings& s, Vec3 wi, std::uint64_t count, Rng& rng,
                        BrdfAccumulator& out);

}  // namespace mcref::volume
