#pragma once
// The data-parallel slab walk's lanes (sim/slab/wave_walk.h): the paths in
// flight in structure-of-arrays form, one per lane, their random streams and
// step outcomes, the layer stack the stages read by selects, and what the
// stages need to vectorise (GCC 12).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/slab/wave_walk.h"

// The vector stages (sim/slab/wave_walk.cpp, wave_grid_flights.cpp) are built for AVX-512 (x86-64-v4), AVX2 (x86-64-v3)
// and baseline x86-64, the loader picking one (GCC function multi-versioning).
// Those files are compiled without FMA contraction (CMakeLists.txt), so every
// version computes the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define MCREF_WAVE_STAGE __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#else
#define MCREF_WAVE_STAGE
#endif

namespace mcref::volume::wave {

constexpr int N = kWaveLanes;
// Small integers are held as doubles in the lanes: a loop then has one lane
// type, which the vectoriser needs for its selects.
constexpr double kCollision = 0, kTop = 1, kBottom = 2, kLost = 3;  // flight outcomes
// (OpenVDB layers) a null collision: no event, the path flies on from there; a
// tentative collision that the cell's bounds do not decide (kLookup: resolved
// from the voxels before the phase events).
constexpr double kNull = 4, kLookup = 5;
// (OpenVDB depth profiles) a flight the vector stage left to the scalar pass.
constexpr double kDeferred = 6;
constexpr double kGoesOn = 0, kEnded = 1, kScalar = 2;              // lane status after a step

// The paths in flight, one per lane.
struct Paths {
  alignas(64) double dx[N], dy[N], dz[N];  // propagation direction
  alignas(64) double depth[N];
  alignas(64) double wr[N], wg[N], wb[N];  // RGB weight
  alignas(64) double order[N], first_class[N], delta[N];
  alignas(64) double layer[N];  // index of the layer the path is in

  Rgb weight(int i) const { return {wr[i], wg[i], wb[i]}; }
  void start(int i, Vec3 d) {
    dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
    depth[i] = 0, layer[i] = 0;
    wr[i] = wg[i] = wb[i] = 1;
    order[i] = 0, first_class[i] = kClassVolume, delta[i] = 1;
  }
  void move(int from, int to) {
    dx[to] = dx[from], dy[to] = dy[from], dz[to] = dz[from], depth[to] = depth[from], layer[to] = layer[from];
    wr[to] = wr[from], wg[to] = wg[from], wb[to] = wb[from];
    order[to] = order[from], first_class[to] = first_class[from], delta[to] = delta[from];
  }
};

// One xoshiro256** generator per lane.
struct Streams {
  alignas(64) std::uint64_t s0[N], s1[N], s2[N], s3[N];

  std::uint64_t next(int i) { return xoshiro256ss_next(s0[i], s1[i], s2[i], s3[i]); }
  // Uniform in [1, 2) with 52 random bits, by the bits alone (no int64 -> double conversion).
  double one_to_two(int i) {
    const std::uint64_t b = (next(i) >> 12) | 0x3ff0000000000000ULL;
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
  double uniform(int i) { return one_to_two(i) - 1; }  // [0, 1), exact
  void move(int from, int to) { s0[to] = s0[from], s1[to] = s1[from], s2[to] = s2[from], s3[to] = s3[from]; }
};

// OpenVDB layers: the lateral position in the tile, [0, tile), and a tentative
// collision's acceptance draw (kLookup lanes), or the column still to go
// (kDeferred lanes). Not double-buffered: the phase events leave them as they are.
struct Lateral {
  alignas(64) double x[N], y[N], v[N];
  void move(int from, int to) { x[to] = x[from], y[to] = y[from]; }
};

// What the last step did to each lane.
struct Steps {
  alignas(64) double event[N];   // outcome of the flight
  alignas(64) double status[N];  // kGoesOn, kEnded, or kScalar (left the layer: scalar code decides)
  alignas(64) double keep[N];    // a phase event's survival probability in the roulette (0: an invalid sample)
};

// The next-event tallies of each lane's phase event (walk.h's estimators), as the
// vector stage computes them in a stack of homogeneous layers, for the scalar
// pass to add: the factor of the weight after the event along the new direction,
// and (next_event_mis) the uniform direction and its contribution. 0: no tally.
struct NextEvents {
  alignas(64) double along_d[N];
  alignas(64) double ux[N], uy[N], uz[N];
  alignas(64) double ur[N], ug[N], ub[N];
  alignas(64) double sigma_wi[N];  // (scratch: sigma(wi) of the lane's layer, SGGX)
};

// Everything the stages touch, in one object (so the compiler sees that no two
// arrays overlap). The scatter stage reads one of a and b and writes the other.
struct Lanes {
  Paths a, b;
  Streams r;
  Steps st;
  Lateral pos;
  NextEvents ne;
  template <bool kB>
  Paths& paths() {
    if constexpr (kB) return b; else return a;
  }
};

// The stack's layers (at most kMaxLayers; one phase family), copied into the
// stages (locals: no aliasing with the lanes). A lane reads its layer's values
// by selects on its layer index (pick): gathers through the index would stop
// the vectoriser.
constexpr int kMaxLayers = 4;
struct Stack {
  SlabPhase phase;  // of layer 0; the others are of the same family (SGGX, or the same kind)
  int layers;
  double top[kMaxLayers], bottom[kMaxLayers], density[kMaxLayers], g[kMaxLayers];
  double S[9][kMaxLayers], L[9][kMaxLayers];  // SGGX matrix and its Cholesky factor, row-major
  double S_inv[9][kMaxLayers], sqrt_det[kMaxLayers];  // its inverse and sqrt(det S) (the NDF)
  double ar[kMaxLayers], ag[kMaxLayers], ab[kMaxLayers], fr[kMaxLayers], fg[kMaxLayers], fb[kMaxLayers];
};

// v[layer] for a lane in `layer` (0 <= layer < K), as selects.
// (Unrolled before the vectoriser sees them: a loop inside the lane loop stops it.)
template <int K>
inline double pick(const double (&v)[kMaxLayers], double layer) {
  double r = v[0];
#pragma GCC unroll 4
  for (int k = 1; k < K; ++k) r = layer == k ? v[k] : r;
  return r;
}

template <int K>
inline sggx::Mat3 pick_matrix(const double (&m)[9][kMaxLayers], double layer) {
  sggx::Mat3 r;
#pragma GCC unroll 9
  for (int e = 0; e < 9; ++e) r.m[e / 3][e % 3] = pick<K>(m[e], layer);
  return r;
}

// sigma(w; S) of the lane's layer (SpongeCake Eq. 3, sggx::projected_area); 1
// for the other phase functions (sigma_t = rho).
template <bool kSggx, int K>
inline double sigma_of(const Stack& l, double layer, Vec3 w) {
  if constexpr (kSggx)
    return std::sqrt(std::max(0.0, sggx::quadratic_form(pick_matrix<K>(l.S, layer), w)));
  else
    return 1.0;
}

}  // namespace mcref::volume::wave
