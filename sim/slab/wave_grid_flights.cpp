#include "sim/slab/wave_grid_flights.h"

#include <algorithm>
#include <cmath>

#include "models/core/simd_log.h"

namespace mcref::volume::wave {

namespace {

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
    const double mu = rho_max * sigma_of<kSggx, K>(l, k, d);
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

}  // namespace

void fly_grid(Lanes& L, bool in_b, int n, const Stack& l, const Grid& g, const float* lo, const float* hi,
              const int* depth_cell) {
  if (g.lateral && g.depth) fly_grid_lateral_depth(L, in_b, n, l, g, lo, hi, depth_cell);
  if (g.lateral && !g.depth) fly_grid_lateral(L, in_b, n, l, g, lo, hi, depth_cell);
  if (!g.lateral && g.depth) fly_grid_depth(L, in_b, n, l, g, lo, hi, depth_cell);
  if (!g.lateral && !g.depth) fly_grid_uniform(L, in_b, n, l, g, lo, hi, depth_cell);
}

namespace {

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
    const double f = sigma_of<kSggx, K>(l, k, d);
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

MCREF_WAVE_STAGE void fly_profile_stage(Lanes& L, bool in_b, int n, const Stack& l, const Profiles& q, const double* rho,
                                        const double* column, const int* interval_of) {
  if (l.layers == 1) fly_profile_stack<1>(L, in_b, n, l, q, rho, column, interval_of);
  else if (l.layers == 2) fly_profile_stack<2>(L, in_b, n, l, q, rho, column, interval_of);
  else fly_profile_stack<kMaxLayers>(L, in_b, n, l, q, rho, column, interval_of);
}

}  // namespace

void fly_profiles(Lanes& L, bool in_b, int n, const Stack& l, const Profiles& q, const double* rho,
                  const double* column, const int* interval_of) {
  fly_profile_stage(L, in_b, n, l, q, rho, column, interval_of);
}

}  // namespace mcref::volume::wave
