#include "sim/slab/wave_walk.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "models/core/frame.h"
#include "models/core/simd_log.h"
#include "models/core/small_angle.h"
#include "models/core/warp.h"
#include "models/sggx/flake_phase.h"
#include "models/sggx/hg_phase.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/slab/depth_profile.h"
#include "sim/slab/substrate.h"
#include "sim/slab/voxel_density.h"

// The two vector stages are built for AVX-512 (x86-64-v4), AVX2 (x86-64-v3)
// and baseline x86-64, the loader picking one (GCC function multi-versioning).
// This file is compiled without FMA contraction (CMakeLists.txt), so every
// version computes the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define MCREF_WAVE_STAGE __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#else
#define MCREF_WAVE_STAGE
#endif

namespace mcref::volume {

namespace {

constexpr int N = kWaveLanes;
// Small integers are held as doubles in the lanes: a loop then has one lane
// type, which the vectoriser needs for its selects.
constexpr double kCollision = 0, kTop = 1, kBottom = 2, kLost = 3;  // flight outcomes
// (OpenVDB layers) a null collision: no event, the path flies on from there; a
// tentative collision that the cell's bounds do not decide (kLookup: resolved
// from the voxels before the phase events).
constexpr double kNull = 4, kLookup = 5;
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
};

// Everything the stages touch, in one object (so the compiler sees that no two
// arrays overlap). The scatter stage reads one of a and b and writes the other.
struct Lanes {
  Paths a, b;
  Streams r;
  Steps st;
  Lateral pos;
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

// Russian roulette once order >= from (walk.h): survives with probability
// p = min(1, max weight), the weight divided by p. A zero weight (p = 0) ends
// the path there; at lower orders the path goes on, adding zeros to the tally,
// where walk() ends it. u uniform in [0, 1). Returns 1 if the path goes on,
// else 0 (flags are doubles in lane code: booleans combined there stop the
// vectoriser).
inline double roulette(double& r, double& g, double& b, double order, double from, double u) {
  const double p = order >= from ? std::min(1.0, std::max(r, std::max(g, b))) : 1.0;
  const double k = 1 / std::max(p, 0x1p-1022);  // (p = 0: the weights are 0)
  r *= k, g *= k, b *= k;
  return u < p ? 1.0 : 0.0;
}

// The direction at cosine c from the unit axis, azimuth 2 pi u about it.
inline Vec3 deflect(Vec3 axis, double c, double u) {
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  const SinCos phi = sincos_turn_unit(u);
  return normalize(Frame(axis).to_world({s * phi.cos, s * phi.sin, c}));
}

// Free flights to the next collision in the lane's layer or to a face of it
// (exact exponential, sigma_t = rho sigma(w), Eq. 3), as free_flight.cpp's
// track(); a path that reaches an inner face crosses it in the scalar pass and
// draws a new exponential there (the same law: it is memoryless).
// (The stages copy what they read of the stack into locals: conditional loads
// through a pointer would stop the loop's if-conversion.)
template <bool kSggx, bool kB, int K>
inline void fly_lanes(Lanes& L, int n, const Stack& stack) {
  const Stack l = stack;
  Paths& p = L.paths<kB>();
  Streams& r = L.r;
  Steps& st = L.st;
  for (int i = 0; i < n; ++i) {
    const Vec3 d{p.dx[i], p.dy[i], p.dz[i]};
    const double k = p.layer[i];
    const double tau = -simd_log(2 - r.one_to_two(i));  // -log(1 - u), 1 - u in (0, 1]
    const double density = pick<K>(l.density, k), top = pick<K>(l.top, k), bottom = pick<K>(l.bottom, k);
    double mu = density;
    if constexpr (kSggx) {
      const sggx::Mat3 S = pick_matrix<K>(l.S, k);
      mu *= std::sqrt(std::max(0.0, sggx::quadratic_form(S, d)));  // sggx::projected_area
    }
    const double rate = -d.z, depth = p.depth[i];  // d(depth)/ds
    const double dist = rate > 0 ? (bottom - depth) / rate : rate < 0 ? (top - depth) / rate : INFINITY;
    const bool collide = tau < mu * dist;
    p.depth[i] = collide ? depth + rate * (tau / mu) : rate > 0 ? bottom : top;
    st.event[i] = collide ? kCollision : !(dist < INFINITY) ? kLost : rate > 0 ? kBottom : kTop;
  }
}

template <int K>
inline void fly_stack(Lanes& L, bool in_b, int n, const Stack& l) {
  const bool sggx = l.phase == SlabPhase::kSggxSurface || l.phase == SlabPhase::kSggxFiber;
  if (sggx && in_b) fly_lanes<true, true, K>(L, n, l);
  if (sggx && !in_b) fly_lanes<true, false, K>(L, n, l);
  if (!sggx && in_b) fly_lanes<false, true, K>(L, n, l);
  if (!sggx && !in_b) fly_lanes<false, false, K>(L, n, l);
}

// (On paths b if in_b, else a.)
MCREF_WAVE_STAGE void fly(Lanes& L, bool in_b, int n, const Stack& l) {
  if (l.layers == 1) fly_stack<1>(L, in_b, n, l);
  else if (l.layers == 2) fly_stack<2>(L, in_b, n, l);
  else fly_stack<kMaxLayers>(L, in_b, n, l);
}

// OpenVDB layers (S the same everywhere in each): delta tracking against the
// layer's majorant rho_max sigma(w; S) (the Stack's density is rho_max, the max
// of the layer's cell majorants hi, sim/slab/majorant_grid.h), exact in
// direction; a tentative collision at x is real with probability
// rho(x) / rho_max, decided by u rho_max against its cell's bounds lo <= rho <= hi
// (real below lo, null from hi) and, in between, from the voxels (kLookup).
// Cells: the majorants' own (lateral m x m per tile, depth runs of voxel
// intervals), read from the medium's flat tables (sim/slab/cell_bounds.h),
// passed beside this.
struct Grid {
  double offset[kMaxLayers], depth_offset[kMaxLayers], m[kMaxLayers], inv_cell[kMaxLayers], inv_hz[kMaxLayers];
  double intervals;          // voxel intervals per layer in depth
  double last;               // the last cell's index
  double tile, inv_tile;     // lateral period
  bool lateral, depth;       // some layer varies laterally; some layer has more than one depth cell
};

// Attempts per step: a lane whose tentative collisions were all null takes no
// event in this step (kNull) and flies on in the next.
constexpr int kAttempts = 2;

// v - n floor(v / n) (inv_n = 1 / n): in [0, n] (n only by rounding).
inline double wrap_tile(double v, double n, double inv_n) { return v - n * std::floor(v * inv_n); }

// kLateral: some layer varies laterally (else x and y stay 0);
// kDepth: some layer has more than one depth cell.
template <bool kSggx, bool kB, int K, bool kLateral, bool kDepth>
inline void fly_grid_lanes(Lanes& L, int n, const Stack& stack, const Grid& grid, const float* table_lo,
                           const float* table_hi, const int* table_depth_cell) {
  const Stack l = stack;
  const Grid g = grid;
  Paths& p = L.paths<kB>();
  Streams& r = L.r;
  Steps& st = L.st;
  Lateral& pos = L.pos;
  for (int i = 0; i < n; ++i) {
    const Vec3 d{p.dx[i], p.dy[i], p.dz[i]};
    const double k = p.layer[i];
    const double rho_max = pick<K>(l.density, k), top = pick<K>(l.top, k), bottom = pick<K>(l.bottom, k);
    const double offset = pick<K>(g.offset, k), depth_offset = pick<K>(g.depth_offset, k), m = pick<K>(g.m, k);
    const double inv_cell = pick<K>(g.inv_cell, k), inv_hz = pick<K>(g.inv_hz, k);
    double mu = rho_max;
    if constexpr (kSggx) {
      const sggx::Mat3 S = pick_matrix<K>(l.S, k);
      mu *= std::sqrt(std::max(0.0, sggx::quadratic_form(S, d)));  // sggx::projected_area
    }
    const double rate = -d.z;  // d(depth)/ds
    // (Divisions once per step, not per attempt.)
    const double face = rate > 0 ? bottom : top, inv_rate = 1 / rate, inv_mu = 1 / mu;
    double depth = p.depth[i], x = pos.x[i], y = pos.y[i], v = 0, event = kNull;
#pragma GCC unroll 4
    for (int a = 0; a < kAttempts; ++a) {
      const double tau = -simd_log(2 - r.one_to_two(i));  // -log(1 - u), 1 - u in (0, 1]
      const double u = r.uniform(i);
      const double dist = rate != 0 ? (face - depth) * inv_rate : INFINITY;
      const bool collide = tau < mu * dist;
      const double s = collide ? tau * inv_mu : dist < INFINITY ? dist : 0.0;
      const double depth1 = collide ? depth + rate * s : face;
      // The tentative collision's cell (clamped: rounding, and lanes that left).
      double x1 = 0, y1 = 0, cx = 0, cy = 0, cz = 0;
      if constexpr (kLateral) {
        x1 = wrap_tile(x + d.x * s, g.tile, g.inv_tile), y1 = wrap_tile(y + d.y * s, g.tile, g.inv_tile);
        cx = std::min(m - 1, std::floor(x1 * inv_cell)), cy = std::min(m - 1, std::floor(y1 * inv_cell));
      }
      if constexpr (kDepth) {
        const double vz = std::min(g.intervals - 1, std::max(0.0, std::floor((depth1 - top) * inv_hz)));
        cz = table_depth_cell[static_cast<int>(depth_offset + vz)];  // (int -> double: exact)
      }
      const double cell = std::min(g.last, std::max(0.0, offset + (cz * m + cy) * m + cx));
      const int c = static_cast<int>(cell);
      const double v1 = u * rho_max, lo = table_lo[c], hi = table_hi[c];
      // (Two-way selects, as flags: a select of more values stops the vectoriser.)
      const double exit = dist < INFINITY ? (rate > 0 ? kBottom : kTop) : kLost;
      const double tentative = v1 < lo ? kCollision : v1 >= hi ? kNull : kLookup;
      const double hit = collide ? 1.0 : 0.0;
      const double outcome = hit * tentative + (1 - hit) * exit;
      const bool pending = event == kNull;
      depth = pending ? depth1 : depth, x = pending ? x1 : x, y = pending ? y1 : y;
      v = pending ? v1 : v;
      event = pending ? outcome : event;
    }
    p.depth[i] = depth, pos.x[i] = x, pos.y[i] = y, pos.v[i] = v;
    st.event[i] = event;
  }
}

template <int K, bool kLateral, bool kDepth>
inline void fly_grid_stack(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo,
                           const float* hi, const int* depth_cell) {
  const bool sggx = l.phase == SlabPhase::kSggxSurface || l.phase == SlabPhase::kSggxFiber;
  if (sggx && in_b) fly_grid_lanes<true, true, K, kLateral, kDepth>(L, n, l, g, lo, hi, depth_cell);
  if (sggx && !in_b) fly_grid_lanes<true, false, K, kLateral, kDepth>(L, n, l, g, lo, hi, depth_cell);
  if (!sggx && in_b) fly_grid_lanes<false, true, K, kLateral, kDepth>(L, n, l, g, lo, hi, depth_cell);
  if (!sggx && !in_b) fly_grid_lanes<false, false, K, kLateral, kDepth>(L, n, l, g, lo, hi, depth_cell);
}

template <bool kLateral, bool kDepth>
inline void fly_grid_cells(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo, const float* hi,
                           const int* depth_cell) {
  if (l.layers == 1) fly_grid_stack<1, kLateral, kDepth>(L, in_b, n, l, g, lo, hi, depth_cell);
  else if (l.layers == 2) fly_grid_stack<2, kLateral, kDepth>(L, in_b, n, l, g, lo, hi, depth_cell);
  else fly_grid_stack<kMaxLayers, kLateral, kDepth>(L, in_b, n, l, g, lo, hi, depth_cell);
}

// One stage per kind of cells (in one function, GCC stops vectorising some of them).
MCREF_WAVE_STAGE void fly_grid_lateral_depth(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo,
                                             const float* hi, const int* depth_cell) {
  fly_grid_cells<true, true>(L, in_b, n, l, g, lo, hi, depth_cell);
}
MCREF_WAVE_STAGE void fly_grid_lateral(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo,
                                       const float* hi, const int* depth_cell) {
  fly_grid_cells<true, false>(L, in_b, n, l, g, lo, hi, depth_cell);
}
MCREF_WAVE_STAGE void fly_grid_depth(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo,
                                     const float* hi, const int* depth_cell) {
  fly_grid_cells<false, true>(L, in_b, n, l, g, lo, hi, depth_cell);
}
MCREF_WAVE_STAGE void fly_grid_uniform(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo,
                                       const float* hi, const int* depth_cell) {
  fly_grid_cells<false, false>(L, in_b, n, l, g, lo, hi, depth_cell);
}

void fly_grid(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo, const float* hi,
              const int* depth_cell) {
  if (g.lateral && g.depth) fly_grid_lateral_depth(L, in_b, n, l, g, lo, hi, depth_cell);
  if (g.lateral && !g.depth) fly_grid_lateral(L, in_b, n, l, g, lo, hi, depth_cell);
  if (!g.lateral && g.depth) fly_grid_depth(L, in_b, n, l, g, lo, hi, depth_cell);
  if (!g.lateral && !g.depth) fly_grid_uniform(L, in_b, n, l, g, lo, hi, depth_cell);
}

// OpenVDB stacks whose layers all vary in depth only, each with one S (every
// stack a TOML describes): exact flights, as free_flight.cpp's fly_profile
// (sim/slab/depth_profile.h). The column of rho to go is tau |w_z| / sigma(w);
// from the start's column, the interval where the column reaches its target is
// the table's guess or the one after it (else, for thin intervals, the scalar
// pass flies the lane: kDeferred, the column to go in Lateral::v); then one
// quadratic. No null collisions, no voxel lookups. A path that reaches an inner
// face crosses it in the scalar pass and draws a new exponential there (the
// same law: it is memoryless). Layer k's planes (rho, column) and table
// entries start at plane0[k] and entry0[k] of the flat tables passed beside this.
struct Profiles {
  double plane0[kMaxLayers], entry0[kMaxLayers], entries[kMaxLayers];
  double last[kMaxLayers];      // the last interval's index (planes - 2)
  double inv_step[kMaxLayers];  // table entries per unit of column (index units: rho x planes)
  double total[kMaxLayers];     // the layer's whole column
  double hz[kMaxLayers], inv_hz[kMaxLayers];
};
constexpr double kDeferred = 6;  // (a flight outcome)

template <bool kSggx, bool kB, int K>
inline void fly_profile_lanes(Lanes& L, int n, const Stack& stack, const Profiles& profiles,
                              const double* __restrict rho, const double* __restrict column,
                              const int* __restrict interval_of) {
  const Stack l = stack;
  const Profiles q = profiles;
  Paths& p = L.paths<kB>();
  Streams& r = L.r;
  Steps& st = L.st;
  Lateral& pos = L.pos;
  for (int i = 0; i < n; ++i) {
    const Vec3 d{p.dx[i], p.dy[i], p.dz[i]};
    const double k = p.layer[i];
    const double top = pick<K>(l.top, k), bottom = pick<K>(l.bottom, k), last = pick<K>(q.last, k);
    const double plane0 = pick<K>(q.plane0, k), entry0 = pick<K>(q.entry0, k), entries = pick<K>(q.entries, k);
    const double inv_step = pick<K>(q.inv_step, k), total = pick<K>(q.total, k);
    const double hz = pick<K>(q.hz, k), inv_hz = pick<K>(q.inv_hz, k);
    double f = 1;  // sigma(w)
    if constexpr (kSggx) {
      const sggx::Mat3 S = pick_matrix<K>(l.S, k);
      f = std::sqrt(std::max(0.0, sggx::quadratic_form(S, d)));  // sggx::projected_area
    }
    const double tau = -simd_log(2 - r.one_to_two(i));  // -log(1 - u), 1 - u in (0, 1]
    const double rate = -d.z, depth = p.depth[i];      // d(depth)/ds
    // (Flags as doubles, and two-way selects: booleans combined, or a select of
    // more values, stop the vectoriser; loads on no condition, for the same reason.)
    const double down = rate > 0 ? 1.0 : 0.0, face = rate > 0 ? bottom : top;
    // The column to go, in rho x depth (inf where sigma(w) = 0), and in index units.
    const double amount = tau * std::fabs(rate) / f, need = amount * inv_hz;
    // The start: index u0 (plane 0 on the bottom face), in interval j0; its column g0.
    const double u0 = std::min(last + 1, std::max(0.0, (bottom - depth) * inv_hz));
    const double j0 = std::min(last, std::floor(u0)), t0 = u0 - j0;
    const int c0 = static_cast<int>(plane0 + j0);
    const double a0 = rho[c0], s0 = rho[c0 + 1] - a0;
    const double g0 = column[c0] + (a0 + 0.5 * s0 * t0) * t0;
    // The target (deeper is towards plane 0), clamped to the layer for the lanes that leave it.
    const double g = g0 + (1 - 2 * down) * need;
    const double exits = down * (g > 0 ? 0.0 : 1.0) + (1 - down) * (g < total ? 0.0 : 1.0);
    const double gc = std::min(total, std::max(0.0, g));
    // Its interval: the table's guess, or the one after it (j <= last).
    double j = interval_of[static_cast<int>(entry0 + std::min(entries - 1, std::floor(gc * inv_step)))];
    const double guess_end = column[static_cast<int>(plane0 + j) + 1];
    j += (j < last ? 1.0 : 0.0) * (guess_end <= gc ? 1.0 : 0.0);
    const int c = static_cast<int>(plane0 + j);
    const double end = column[c + 1];
    const double further = (j < last ? 1.0 : 0.0) * (end <= gc ? 1.0 : 0.0);  // thin intervals: the scalar pass
    // In interval j, rho = a + s t: the column from plane j is a t + s t^2 / 2 = R (DepthProfile::invert).
    const double a = rho[c], s = rho[c + 1] - a, rr = std::max(0.0, gc - column[c]);
    const double denom = a + std::sqrt(std::max(0.0, a * a + 2 * s * rr));
    const double t = std::min(1.0, 2 * rr / std::max(denom, 0x1p-1022));
    // Horizontal (measure zero): rho is constant along the ray; a collision unless it is 0.
    const double flat = (a0 + s0 * t0) * f > 0 ? kCollision : kLost;
    double event = further > 0 ? kDeferred : kCollision, to = further > 0 ? depth : bottom - (j + t) * hz;
    event = exits > 0 ? kTop + down * (kBottom - kTop) : event;
    to = exits > 0 ? face : to;
    event = rate == 0 ? flat : event;
    to = rate == 0 ? depth : to;
    p.depth[i] = to, pos.v[i] = amount;
    st.event[i] = event;
  }
}

template <int K>
inline void fly_profile_stack(Lanes& L, bool in_b, int n, const Stack& l, const Profiles& q, const double* rho,
                              const double* column, const int* interval_of) {
  const bool sggx = l.phase == SlabPhase::kSggxSurface || l.phase == SlabPhase::kSggxFiber;
  if (sggx && in_b) fly_profile_lanes<true, true, K>(L, n, l, q, rho, column, interval_of);
  if (sggx && !in_b) fly_profile_lanes<true, false, K>(L, n, l, q, rho, column, interval_of);
  if (!sggx && in_b) fly_profile_lanes<false, true, K>(L, n, l, q, rho, column, interval_of);
  if (!sggx && !in_b) fly_profile_lanes<false, false, K>(L, n, l, q, rho, column, interval_of);
}

MCREF_WAVE_STAGE void fly_profiles(Lanes& L, bool in_b, int n, const Stack& l, const Profiles& q, const double* rho,
                                   const double* column, const int* interval_of) {
  if (l.layers == 1) fly_profile_stack<1>(L, in_b, n, l, q, rho, column, interval_of);
  else if (l.layers == 2) fly_profile_stack<2>(L, in_b, n, l, q, rho, column, interval_of);
  else fly_profile_stack<kMaxLayers>(L, in_b, n, l, q, rho, column, interval_of);
}

// The phase-function event of every lane that collided, as walk() does it
// (order, first class, weight, direction, roulette), from `in` into `out`;
// the other lanes are copied. The draws are made for every lane, and unused
// where the flight left the layer. (Into other arrays: a store of an unchanged
// value back into its own array would be dropped, and the store become
// conditional, which stops the vectoriser.)
template <SlabPhase kPhase, bool kFromB, int K>
inline void scatter_lanes(Lanes& L, int n, const Stack& stack, int max_order, int roulette_from) {
  const Stack l = stack;
  const double cap = max_order > 0 ? max_order : INFINITY, from = roulette_from;  // order cap, roulette start
  const Paths& in = L.paths<kFromB>();
  Paths& out = L.paths<!kFromB>();
  Streams& r = L.r;
  Steps& st = L.st;
  for (int i = 0; i < n; ++i) {
    const Vec3 wi{-in.dx[i], -in.dy[i], -in.dz[i]};
    const double k = in.layer[i];
    const double u1 = r.uniform(i), u2 = r.uniform(i);
    Vec3 wo;
    double fr = pick<K>(l.ar, k), fg = pick<K>(l.ag, k), fb = pick<K>(l.ab, k);
    double valid = 1;
    if constexpr (kPhase == SlabPhase::kSggxSurface) {  // both SGGX kinds: phase.cpp's sample_sggx_flakes
      sggx::Sggx s;
      s.L = pick_matrix<K>(l.L, k);  // all the sampler reads
      const Vec3 m = sggx::sample_visible_normal(s, wi, u1, u2);
      const double c = dot(wi, m), ac = std::fabs(c);
      wo = normalize(m * (2 * c) - wi);
      fr *= sggx::schlick(pick<K>(l.fr, k), ac), fg *= sggx::schlick(pick<K>(l.fg, k), ac),
          fb *= sggx::schlick(pick<K>(l.fb, k), ac);
      valid = c > 0 ? 1.0 : 0.0;
    } else if constexpr (kPhase == SlabPhase::kHenyeyGreenstein) {
      wo = deflect(-wi, sggx::sample_hg_cos_theta(pick<K>(l.g, k), u1), u2);
    } else if constexpr (kPhase == SlabPhase::kIsotropic) {
      wo = sample_uniform_sphere(u1, u2);
    } else {  // Lambert sphere, d'Eon 2021 Eq. 5: mu = sqrt((1 - u1)(1 - u2)) sin(2 pi u3) - sqrt(u1 u2)
      const double u3 = r.uniform(i), u4 = r.uniform(i);
      const double mu = std::sqrt((1 - u1) * (1 - u2)) * sincos_turn_unit(u3).sin - std::sqrt(u1 * u2);
      wo = deflect(-wi, mu, u4);
    }
    const double u_roulette = r.uniform(i);
    const double ev = st.event[i], order = in.order[i];
    const double scatter = ev == kCollision ? (order >= cap ? 0.0 : 1.0) : 0.0;  // 1: a phase-function event
    double wr = in.wr[i] * fr, wg = in.wg[i] * fg, wb = in.wb[i] * fb;
    const double alive = valid * roulette(wr, wg, wb, order + 1, from, u_roulette);
    const bool s = scatter > 0;
    st.status[i] = ev == kNull ? kGoesOn : ev != kCollision ? kScalar : scatter * alive > 0 ? kGoesOn : kEnded;
    out.depth[i] = in.depth[i];
    out.layer[i] = k;
    out.order[i] = order + scatter;
    out.first_class[i] = order == 0 ? (s ? kClassVolume : in.first_class[i]) : in.first_class[i];
    out.delta[i] = in.delta[i] * (1 - scatter);
    out.wr[i] = s ? wr : in.wr[i], out.wg[i] = s ? wg : in.wg[i], out.wb[i] = s ? wb : in.wb[i];
    out.dx[i] = s ? wo.x : in.dx[i], out.dy[i] = s ? wo.y : in.dy[i], out.dz[i] = s ? wo.z : in.dz[i];
  }
}

template <SlabPhase kPhase, int K>
inline void scatter_phase(Lanes& L, bool from_b, int n, const Stack& l, int max_order, int roulette_from) {
  if (from_b)
    scatter_lanes<kPhase, true, K>(L, n, l, max_order, roulette_from);
  else
    scatter_lanes<kPhase, false, K>(L, n, l, max_order, roulette_from);
}

template <int K>
inline void scatter_stack(Lanes& L, bool from_b, int n, const Stack& l, int max_order, int roulette_from) {
  switch (l.phase) {
    case SlabPhase::kSggxSurface:
    case SlabPhase::kSggxFiber: scatter_phase<SlabPhase::kSggxSurface, K>(L, from_b, n, l, max_order, roulette_from); break;
    case SlabPhase::kHenyeyGreenstein:
      scatter_phase<SlabPhase::kHenyeyGreenstein, K>(L, from_b, n, l, max_order, roulette_from);
      break;
    case SlabPhase::kIsotropic: scatter_phase<SlabPhase::kIsotropic, K>(L, from_b, n, l, max_order, roulette_from); break;
    case SlabPhase::kLambertSphere:
      scatter_phase<SlabPhase::kLambertSphere, K>(L, from_b, n, l, max_order, roulette_from);
      break;
  }
}

// (From paths b into a if from_b, else from a into b.)
MCREF_WAVE_STAGE void scatter(Lanes& L, bool from_b, int n, const Stack& l, int max_order, int roulette_from) {
  if (l.layers == 1) scatter_stack<1>(L, from_b, n, l, max_order, roulette_from);
  else if (l.layers == 2) scatter_stack<2>(L, from_b, n, l, max_order, roulette_from);
  else scatter_stack<kMaxLayers>(L, from_b, n, l, max_order, roulette_from);
}

// A lane whose flight left its layer (kScalar), as walk() does it: into the
// next layer through an inner face; the tally at the top, or at the bottom
// without a substrate; else a substrate bounce. Returns the lane's new status.
double leave_or_bounce(Paths& p, Streams& r, double ev, int i, const SlabMedium& medium,
                             const WalkSettings& s, BrdfAccumulator& out) {
  const Vec3 d{p.dx[i], p.dy[i], p.dz[i]};
  const int order = static_cast<int>(p.order[i]), first_class = static_cast<int>(p.first_class[i]);
  if (ev == kLost) return kEnded;
  const double next = p.layer[i] + (ev == kTop ? -1 : 1);
  if (next >= 0 && next < static_cast<double>(medium.layers().size())) {
    p.layer[i] = next;
    return kGoesOn;
  }
  if (ev == kTop || !medium.has_substrate()) {
    if (ev == kTop || order > 0 || s.delta_transmission) out.add(d, order, first_class, p.weight(i), p.delta[i] != 0);
    return kEnded;
  }
  if (s.max_order > 0 && order >= s.max_order) return kEnded;
  p.order[i] = order + 1;
  if (order == 0) p.first_class[i] = kClassSubstrate;
  const double u1 = r.uniform(i), u2 = r.uniform(i);
  const SubstrateSample sc = sample_substrate(medium.substrate(), -d, u1, u2);
  if (!sc.valid) return kEnded;
  p.wr[i] *= sc.weight.r, p.wg[i] *= sc.weight.g, p.wb[i] *= sc.weight.b;
  p.dx[i] = sc.wo.x, p.dy[i] = sc.wo.y, p.dz[i] = sc.wo.z;
  p.delta[i] = p.delta[i] && sc.specular;
  return roulette(p.wr[i], p.wg[i], p.wb[i], order + 1, s.roulette_from, r.uniform(i)) > 0 ? kGoesOn : kEnded;
}

}  // namespace

std::string wave_walk_unsupported(const SlabGeometry& g) {
  if (g.layers.size() > kMaxLayers)
    return "the wave walk takes at most " + std::to_string(kMaxLayers) + " layers, not " + std::to_string(g.layers.size());
  for (const SlabLayer& l : g.layers)
    if (l.is_sggx() != g.layers.front().is_sggx() || (!l.is_sggx() && l.phase != g.layers.front().phase))
      return "the wave walk takes layers of one phase function (SGGX surface and fibre flakes mix)";
  return "";
}

std::uint64_t wave_walk(const SlabMedium& medium, const WalkSettings& s, Vec3 wi, std::uint64_t count, Rng& rng,
                        BrdfAccumulator& out) {
  const std::vector<SlabLayer>& layers = medium.geometry().layers;
  Stack l{};
  l.phase = layers.front().phase;
  l.layers = static_cast<int>(layers.size());
  for (int k = 0; k < l.layers; ++k) {
    const SlabLayer& sl = layers[k];
    const sggx::Sggx S = !sl.is_sggx()                            ? sggx::Sggx{}
                         : sl.phase == SlabPhase::kSggxSurface ? sggx::surface_like(sl.alpha, sl.orientation)
                                                               : sggx::fiber_like(sl.alpha, sl.orientation);
    l.top[k] = medium.layers()[k].top, l.bottom[k] = medium.layers()[k].bottom;
    l.density[k] = sl.density, l.g[k] = sl.g;
    for (int e = 0; e < 9; ++e) l.S[e][k] = S.S.m[e / 3][e % 3], l.L[e][k] = S.L.m[e / 3][e % 3];
    l.ar[k] = sl.albedo.r, l.ag[k] = sl.albedo.g, l.ab[k] = sl.albedo.b;
    l.fr[k] = sl.f0.r, l.fg[k] = sl.f0.g, l.fb[k] = sl.f0.b;
  }
  // OpenVDB layers: each layer's majorant density and S, and where its cells' bounds are.
  const bool grid = medium.grids() != nullptr;
  const CellBounds& bounds = medium.cell_bounds();
  Grid g{};
  if (grid) {
    const SlabGrid& sg = medium.geometry().grid;
    g.intervals = sg.depth_voxels;
    g.tile = sg.tile, g.inv_tile = 1 / sg.tile;
    for (int k = 0; k < l.layers; ++k) {
      const LayerMajorants& M = medium.majorants()[k];
      if (M.s_varies) throw std::invalid_argument("the wave walk takes OpenVDB layers whose SGGX matrix is the same everywhere");
      l.density[k] = bounds.rho_max[k];
      if (M.one_s)
        for (int e = 0; e < 9; ++e) l.S[e][k] = M.s.S.m[e / 3][e % 3], l.L[e][k] = M.s.L.m[e / 3][e % 3];
      g.offset[k] = static_cast<double>(bounds.offset[k]);
      g.depth_offset[k] = static_cast<double>(bounds.depth_offset[k]);
      g.m[k] = M.lateral, g.inv_cell[k] = M.inv_cell_size;
      g.inv_hz[k] = sg.depth_voxels / (l.bottom[k] - l.top[k]);
      g.lateral = g.lateral || M.lateral > 1;
      g.depth = g.depth || M.depth_cells() > 1;
    }
    g.last = static_cast<double>(bounds.lo.size() - 1);
  }
  // Stacks of depth profiles only (sim/slab/depth_profile.h): their tables, flat.
  const std::vector<std::optional<DepthProfile>>& dp = medium.depth_profiles();
  const bool exact = grid && std::all_of(dp.begin(), dp.end(), [](const auto& o) { return o.has_value(); });
  Profiles q{};
  std::vector<double> profile_rho, profile_column;
  std::vector<int> profile_interval;
  if (exact)
    for (int k = 0; k < l.layers; ++k) {
      const DepthProfile& P = *dp[k];
      q.plane0[k] = static_cast<double>(profile_rho.size());
      q.entry0[k] = static_cast<double>(profile_interval.size());
      q.entries[k] = static_cast<double>(P.interval_of().size());
      q.last[k] = static_cast<double>(P.rho().size() - 2);
      q.inv_step[k] = P.inv_column_step(), q.total[k] = P.column().back();
      q.hz[k] = P.hz(), q.inv_hz[k] = P.inv_hz();
      profile_rho.insert(profile_rho.end(), P.rho().begin(), P.rho().end());
      profile_column.insert(profile_column.end(), P.column().begin(), P.column().end());
      profile_interval.insert(profile_interval.end(), P.interval_of().begin(), P.interval_of().end());
    }
  const auto L = std::make_unique<Lanes>();
  Streams& r = L->r;
  Steps& st = L->st;
  Lateral& pos = L->pos;
  for (int i = 0; i < N; ++i) r.s0[i] = rng.next_u64(), r.s1[i] = rng.next_u64(), r.s2[i] = rng.next_u64(), r.s3[i] = rng.next_u64();
  // A new path: entering the top face, uniformly over the tile (laterally varying OpenVDB layers).
  const auto start = [&](Paths& p, int i) {
    p.start(i, -wi);
    if (!g.lateral) return;  // (x, y: 0, unused)
    pos.x[i] = r.uniform(i) * g.tile;
    pos.y[i] = r.uniform(i) * g.tile;
  };
  int n = static_cast<int>(std::min<std::uint64_t>(N, count));
  bool in_b = false;  // the paths are in L->b (else L->a)
  for (int i = 0; i < n; ++i) start(L->a, i);
  std::uint64_t started = static_cast<std::uint64_t>(n), events = 0;
  while (n > 0) {
    if (exact) {
      fly_profiles(*L, in_b, n, l, q, profile_rho.data(), profile_column.data(), profile_interval.data());
      Paths& p = in_b ? L->b : L->a;
      for (int i = 0; i < n; ++i)  // flights whose interval the stage did not reach
        if (st.event[i] == kDeferred) {
          const bool down = p.dz[i] < 0;
          double amount = pos.v[i];
          p.depth[i] = dp[static_cast<int>(p.layer[i])]->travel(p.depth[i], down, amount);
          st.event[i] = amount == 0 ? kCollision : down ? kBottom : kTop;
        }
    } else if (grid) {
      fly_grid(*L, in_b, n, l, g, bounds.lo.data(), bounds.hi.data(), bounds.depth_cell.data());
      const Paths& p = in_b ? L->b : L->a;
      for (int i = 0; i < n; ++i)  // tentative collisions the cells' bounds left open
        if (st.event[i] == kLookup)
          st.event[i] = pos.v[i] < medium.voxels()->density(static_cast<int>(p.layer[i]), pos.x[i], pos.y[i], p.depth[i]) ? kCollision : kNull;
    } else {
      fly(*L, in_b, n, l);
    }
    scatter(*L, in_b, n, l, s.max_order, s.roulette_from);
    in_b = !in_b;
    Paths& p = in_b ? L->b : L->a;
    // Ended lanes take the next path, or the last lane (already handled: the
    // loop runs downward) when none is left.
    for (int i = n - 1; i >= 0; --i) {
      double status = st.status[i];
      if (status == kScalar) status = leave_or_bounce(p, r, st.event[i], i, medium, s, out);
      if (status != kEnded) continue;
      events += static_cast<std::uint64_t>(p.order[i]);
      if (started < count) {
        start(p, i);
        ++started;
      } else {
        --n;
        p.move(n, i);
        r.move(n, i);
        pos.move(n, i);
      }
    }
  }
  return events;
}

}  // namespace mcref::volume
