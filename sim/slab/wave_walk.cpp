#include "sim/slab/wave_walk.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "models/core/frame.h"
#include "models/core/simd_exp.h"
#include "models/core/simd_log.h"
#include "models/core/small_angle.h"
#include "models/core/warp.h"
#include "models/sggx/flake_phase.h"
#include "models/sggx/hg_phase.h"
#include "models/sggx/sggx_distribution.h"
#include "sim/slab/depth_profile.h"
#include "sim/slab/next_event.h"
#include "sim/slab/substrate.h"
#include "sim/slab/voxel_density.h"
#include "sim/slab/wave_grid_flights.h"
#include "sim/slab/wave_lanes.h"

namespace mcref::volume {

using namespace wave;

namespace {

// The Russian roulette's survival probability (walk.h): p = min(1, max weight)
// once order >= from, else 1.
inline double survival(double r, double g, double b, double order, double from) {
  return order >= from ? std::min(1.0, std::max(r, std::max(g, b))) : 1.0;
}

// Russian roulette: survives with probability p (survival()), the weight
// divided by p. A zero weight (p = 0) ends the path there; at lower orders the
// path goes on, adding zeros to the tally, where walk() ends it. u uniform in
// [0, 1). Returns 1 if the path goes on, else 0 (flags are doubles in lane
// code: booleans combined there stop the vectoriser).
inline double roulette(double& r, double& g, double& b, double p, double u) {
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
    const double mu = density * sigma_of<kSggx, K>(l, k, d);
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
    const double keep = survival(wr, wg, wb, order + 1, from);
    const double alive = valid * roulette(wr, wg, wb, keep, u_roulette);
    st.keep[i] = valid * keep;
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

// The probability of escaping the stack from the lane's point along w, exp(-tau)
// (escape.cpp's escape_probability through homogeneous layers): 0 for w.z = 0,
// or downward above a substrate (down = 0; else 1).
template <bool kSggx, int K>
inline double escape_lane(const Stack& l, double layer, double depth, Vec3 w, double down) {
  const bool up = w.z > 0;
  const double inv_mu = 1 / std::fabs(w.z);
  double tau = 0;
#pragma GCC unroll 4
  for (int k = 0; k < K; ++k) {  // the layers from the lane's to the face it leaves by
    const double from = layer == k ? depth : up ? l.bottom[k] : l.top[k], to = up ? l.top[k] : l.bottom[k];
    double sigma = 1;
    if constexpr (kSggx) {
      const double(&S)[9][kMaxLayers] = l.S;  // (written out: a loop here would stay a loop for K > 1)
      const sggx::Mat3 Sk{{{S[0][k], S[1][k], S[2][k]}, {S[3][k], S[4][k], S[5][k]}, {S[6][k], S[7][k], S[8][k]}}};
      sigma = std::sqrt(std::max(0.0, sggx::quadratic_form(Sk, w)));
    }
    // (The path length capped: an empty layer along a grazing w adds 0, not NaN; no
    // select on the layer's density, whose branch the vectoriser would not remove.)
    const double t = l.density[k] * sigma * std::min(std::fabs(to - from) * inv_mu, DBL_MAX);
    tau += up ? (k <= layer ? t : 0.0) : (k >= layer ? t : 0.0);  // (a select of booleans stops the vectoriser)
  }
  const double e = simd_exp_nonpositive(-tau);
  return w.z > 0 ? e : w.z < 0 ? e * down : 0.0;  // (a select on a bool argument stops the vectoriser)
}

// The phase function of the lane's layer, wi -> wo (phase.cpp's eval); for SGGX
// flakes sggx::specular_flake_phase, D(h) / (4 sigma(wi)) (Eq. 4), given sigma(wi).
template <SlabPhase kPhase, int K>
inline double phase_lane(const Stack& l, double k, Vec3 wi, Vec3 wo, double sigma_wi) {
  if constexpr (kPhase == SlabPhase::kSggxSurface) {  // both SGGX kinds
    const Vec3 sum = wi + wo;
    const double D = sggx::ndf(pick_matrix<K>(l.S_inv, k), pick<K>(l.sqrt_det, k), sum);
    return dot(sum, sum) > 1e-24 ? D / (4 * sigma_wi) : 0.0;
  } else if constexpr (kPhase == SlabPhase::kHenyeyGreenstein) {
    return sggx::hg_phase(pick<K>(l.g, k), wi, wo);
  } else {
    return 1 / (4 * kPi);
  }
}

// The next-event tallies of every lane's phase event, as next_event.cpp's
// tally_escape (kMis false) and tally_next_event_mis make them, into L.ne, in a
// stack of homogeneous layers. Made for every lane (the scalar pass adds those
// of the lanes that scattered); with kMis, two draws per lane for the uniform
// direction. `in` holds the paths before the event, `p` after it.
template <SlabPhase kPhase, bool kMis, bool kFromB, int K>
inline void next_event_lanes(Lanes& L, int n, const Stack& stack, bool substrate) {
  const Stack l = stack;
  constexpr bool kSggx = kPhase == SlabPhase::kSggxSurface;
  const double pdf_u = substrate ? 1 / (2 * kPi) : 1 / (4 * kPi);
  const double down = substrate ? 0.0 : 1.0, flip = substrate ? -1.0 : 1.0;  // (flags as doubles)
  const Paths& in = L.paths<kFromB>();
  const Paths& p = L.paths<!kFromB>();
  Streams& r = L.r;
  NextEvents& ne = L.ne;
  if constexpr (kMis && kSggx)  // sigma(wi) of the layer (a loop of its own: with the others, no loop would vectorise)
    for (int i = 0; i < n; ++i) ne.sigma_wi[i] = sigma_of<true, K>(l, p.layer[i], {-in.dx[i], -in.dy[i], -in.dz[i]});
  for (int i = 0; i < n; ++i) {  // along the new direction
    const Vec3 d{p.dx[i], p.dy[i], p.dz[i]}, wi{-in.dx[i], -in.dy[i], -in.dz[i]};
    const double e = escape_lane<kSggx, K>(l, p.layer[i], p.depth[i], d, down);
    if constexpr (!kMis) {
      ne.along_d[i] = e;
    } else {
      const double f = phase_lane<kPhase, K>(l, p.layer[i], wi, d, kSggx ? ne.sigma_wi[i] : 1.0);
      ne.along_d[i] = e > 0 ? e * f / (f + pdf_u) : 0.0;
    }
  }
  if constexpr (kMis)
    for (int i = 0; i < n; ++i) {  // along a uniform direction (a loop of its own: one would not vectorise)
      const Vec3 wi{-in.dx[i], -in.dy[i], -in.dz[i]};
      const double k = p.layer[i], depth = p.depth[i];
      const double u1 = r.uniform(i), u2 = r.uniform(i);
      Vec3 u = sample_uniform_sphere(u1, u2);
      u.z = std::max(u.z, flip * u.z);  // |u.z| above a substrate
      const double fu = phase_lane<kPhase, K>(l, k, wi, u, kSggx ? ne.sigma_wi[i] : 1.0);
      const double eu = escape_lane<kSggx, K>(l, k, depth, u, down);
      const double w = fu > 0 ? (eu > 0 ? eu * fu / (fu + pdf_u) : 0.0) : 0.0;
      double ar = pick<K>(l.ar, k), ag = pick<K>(l.ag, k), ab = pick<K>(l.ab, k);
      if constexpr (kSggx) {  // the flakes' reflectance at h (phase.cpp's albedo)
        const double c = std::fabs(dot(wi, normalize(wi + u)));
        ar *= sggx::schlick(pick<K>(l.fr, k), c), ag *= sggx::schlick(pick<K>(l.fg, k), c),
            ab *= sggx::schlick(pick<K>(l.fb, k), c);
      }
      ne.ux[i] = u.x, ne.uy[i] = u.y, ne.uz[i] = u.z;
      ne.ur[i] = in.wr[i] * ar * w, ne.ug[i] = in.wg[i] * ag * w, ne.ub[i] = in.wb[i] * ab * w;
    }
}

template <SlabPhase kPhase, bool kMis, int K>
inline void next_event_phase(Lanes& L, bool from_b, int n, const Stack& l, bool substrate) {
  if (from_b)
    next_event_lanes<kPhase, kMis, true, K>(L, n, l, substrate);
  else
    next_event_lanes<kPhase, kMis, false, K>(L, n, l, substrate);
}

template <bool kMis, int K>
inline void next_event_stack(Lanes& L, bool from_b, int n, const Stack& l, bool substrate) {
  switch (l.phase) {
    case SlabPhase::kSggxSurface:
    case SlabPhase::kSggxFiber: next_event_phase<SlabPhase::kSggxSurface, kMis, K>(L, from_b, n, l, substrate); break;
    case SlabPhase::kHenyeyGreenstein:
      next_event_phase<SlabPhase::kHenyeyGreenstein, kMis, K>(L, from_b, n, l, substrate);
      break;
    case SlabPhase::kIsotropic: next_event_phase<SlabPhase::kIsotropic, kMis, K>(L, from_b, n, l, substrate); break;
    case SlabPhase::kLambertSphere: break;  // (its phase function: the scalar pass)
  }
}

// (Paths before the event in b if from_b, else in a.)
MCREF_WAVE_STAGE void next_events(Lanes& L, bool from_b, int n, const Stack& l, bool mis, bool substrate) {
  if (mis && l.layers == 1) next_event_stack<true, 1>(L, from_b, n, l, substrate);
  else if (mis && l.layers == 2) next_event_stack<true, 2>(L, from_b, n, l, substrate);
  else if (mis) next_event_stack<true, kMaxLayers>(L, from_b, n, l, substrate);
  else if (l.layers == 1) next_event_stack<false, 1>(L, from_b, n, l, substrate);
  else if (l.layers == 2) next_event_stack<false, 2>(L, from_b, n, l, substrate);
  else next_event_stack<false, kMaxLayers>(L, from_b, n, l, substrate);
}

// The lane's photon (its lateral position where the layers vary laterally, else 0).
Photon photon(const Paths& p, const Lateral& pos, bool lateral, int i) {
  Photon ph;
  ph.x = lateral ? pos.x[i] : 0.0;
  ph.y = lateral ? pos.y[i] : 0.0;
  ph.depth = p.depth[i];
  ph.d = {p.dx[i], p.dy[i], p.dz[i]};
  ph.layer = static_cast<int>(p.layer[i]);
  return ph;
}

// The next-event tally of a lane's substrate bounce (its lane's stream seeds the
// draws, made only through laterally varying layers).
[[gnu::noinline]] void tally_bounce(const Paths& p, Streams& r, const Lateral& pos, bool lateral, int i,
                                   const SlabMedium& medium, BrdfAccumulator& out) {
  Rng lane(r.next(i));
  tally_escape(medium, photon(p, pos, lateral, i), static_cast<int>(p.order[i]), static_cast<int>(p.first_class[i]),
               p.weight(i), p.delta[i] != 0, lane, out);
}

// A lane whose flight left its layer (kScalar), as walk() does it: into the
// next layer through an inner face; the tally at the top, or at the bottom
// without a substrate (with a next-event estimator, only order 0 there); else
// a substrate bounce (and its next-event tally, before the roulette). Returns
// the lane's new status.
double leave_or_bounce(Paths& p, Streams& r, const Lateral& pos, bool lateral, double ev, int i,
                       const SlabMedium& medium, const WalkSettings& s, BrdfAccumulator& out) {
  const Vec3 d{p.dx[i], p.dy[i], p.dz[i]};
  const int order = static_cast<int>(p.order[i]), first_class = static_cast<int>(p.first_class[i]);
  if (ev == kLost) return kEnded;
  const double next = p.layer[i] + (ev == kTop ? -1 : 1);
  if (next >= 0 && next < static_cast<double>(medium.layers().size())) {
    p.layer[i] = next;
    return kGoesOn;
  }
  if (ev == kTop || !medium.has_substrate()) {
    if (tallies_exit(s, ev == kTop, order)) out.add(d, order, first_class, p.weight(i), p.delta[i] != 0);
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
  if (s.estimator != SlabEstimator::kAnalog) tally_bounce(p, r, pos, lateral, i, medium, out);
  const double keep = survival(p.wr[i], p.wg[i], p.wb[i], order + 1, s.roulette_from);
  return roulette(p.wr[i], p.wg[i], p.wb[i], keep, r.uniform(i)) > 0 ? kGoesOn : kEnded;
}

// The stack's layer k takes S (with what the stages read of it).
void set_sggx(Stack& l, int k, const sggx::Sggx& S) {
  for (int e = 0; e < 9; ++e)
    l.S[e][k] = S.S.m[e / 3][e % 3], l.L[e][k] = S.L.m[e / 3][e % 3], l.S_inv[e][k] = S.S_inv.m[e / 3][e % 3];
  l.sqrt_det[k] = S.sqrt_det;
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
    set_sggx(l, k, S);
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
        set_sggx(l, k, M.s);
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
  // The next-event tallies of a lane's phase-function event (walk.h), from its
  // path before the event and after it, with the weight before the roulette
  // (after it, times its survival probability), as walk() tallies them: whether
  // or not the roulette keeps the path. The lane's stream seeds the event's draws.
  const bool next_event = s.estimator != SlabEstimator::kAnalog, mis = s.estimator == SlabEstimator::kNextEventMis;
  // In a stack of homogeneous layers (but of Lambert spheres) the vector stage
  // computes them (next_events, L->ne; its uniform directions drawn from the
  // lanes' streams), and this pass adds them.
  const bool vector_tallies = next_event && !grid && l.phase != SlabPhase::kLambertSphere;
  const bool substrate = medium.has_substrate();
  const auto tally_vector = [&](const Paths& p, int i) {
    const NextEvents& ne = L->ne;
    const int order = static_cast<int>(p.order[i]), first_class = static_cast<int>(p.first_class[i]);
    if (ne.along_d[i] > 0) out.add({p.dx[i], p.dy[i], p.dz[i]}, order, first_class, p.weight(i) * st.keep[i] * ne.along_d[i], false);
    if (mis && (ne.ur[i] > 0 || ne.ug[i] > 0 || ne.ub[i] > 0))
      out.add({ne.ux[i], ne.uy[i], ne.uz[i]}, order, first_class, {ne.ur[i], ne.ug[i], ne.ub[i]}, false);
  };
  const auto tally_next_event = [&](const Paths& in, const Paths& p, int i) {
    Rng lane(r.next(i));
    const Photon ph = photon(p, pos, g.lateral, i);
    const int order = static_cast<int>(p.order[i]), first_class = static_cast<int>(p.first_class[i]);
    const Rgb after = p.weight(i) * st.keep[i];
    if (s.estimator == SlabEstimator::kNextEventMis)
      tally_next_event_mis(medium, ph, {-in.dx[i], -in.dy[i], -in.dz[i]}, in.weight(i), after, order, first_class, lane, out);
    else
      tally_escape(medium, ph, order, first_class, after, false, lane, out);
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
    const Paths& before = in_b ? L->b : L->a;  // (the scatter stage left them as they were)
    in_b = !in_b;
    Paths& p = in_b ? L->b : L->a;
    if (vector_tallies) next_events(*L, !in_b, n, l, mis, substrate);
    if (next_event)
      for (int i = 0; i < n; ++i)
        if (p.order[i] > before.order[i] && st.keep[i] > 0) {  // a phase event (a valid sample)
          if (vector_tallies) tally_vector(p, i);
          else tally_next_event(before, p, i);
        }
    // Ended lanes take the next path, or the last lane (already handled: the
    // loop runs downward) when none is left.
    for (int i = n - 1; i >= 0; --i) {
      double status = st.status[i];
      if (status == kScalar) status = leave_or_bounce(p, r, pos, g.lateral, st.event[i], i, medium, s, out);
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
