#include "sim/micrograin/micrograin_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>

#include "models/core/rng.h"
#include "sim/micrograin/packet_order.h"
#include "sim/micrograin/ray_log.h"

namespace mcref {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// A ray that wraps this often without hitting anything is travelling
// (numerically) horizontally above the grains; it is reported as escaping.
constexpr int kMaxWraps = 1 << 20;
// Step past a spurious self-hit (unit-space length).
constexpr float kSkip = 1e-4f;

// The float origin of a ray leaving a grain can sit inside that grain by
// ~1e-7 of the tile size. A context filter rejects such self-hits inside
// Embree's traversal (a convex grain is not met again by a ray leaving it).
struct LeavingContext : RTCIntersectContext {
  const GrainCopy* prims;
  const Vec3* origin;
  std::uint32_t leaving;
};

void reject_self_hit(const RTCFilterFunctionNArguments* args) {
  const auto* c = static_cast<const LeavingContext*>(args->context);
  const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, 0);
  if (c->prims[prim].owner != c->leaving) return;
  const Vec3 oc = *c->origin - c->prims[prim].centre;  // the copy the origin lies on, not a ghost
  if (std::fabs(dot(oc, oc) - 1) < 1e-6) args->valid[0] = 0;
}
}  // namespace

// One straight piece of a trace inside the tile, up to a side, the base or
// the top of the grain layer, and the rtcIntersect1 call it needs. The call's
// ray is written once, where it is computed: copying it from another record
// right before the call would read back floats still in the store buffer, in
// pieces that straddle two stores (a failed store forward, on every ray).
struct TraceSegment {
  RTCRayHit rh;       // the call (unless `escape`), then Embree's answer in rh.hit and rh.ray.tfar
  float tfar;         // the call's tfar (Embree shortens rh.ray.tfar to its hit): the base or top
  float side_far;     // hits beyond this float distance lie past a side: not in this segment
  std::uint32_t leaving;  // the grain the ray leaves (self-hit filter), or kNoGrain
  Vec3 o, d;          // unit-space origin (in the tile) and direction
  double a, inv_a;    // d . d and its inverse (sphere roots)
  double tx, ty, tz;  // to the x side, the y side, and the base (d.z < 0) or top (d.z > 0) ahead
  double t_side;      // the nearer side: min(tx, ty)
  bool up;            // d.z > 0
  double travelled;   // t before this segment (earlier segments, across wraps)
  int wraps;          // sides crossed before this segment
  bool escape;        // above every grain and going up: no call needed
};

MicrograinField::MicrograinField(const MicrograinGeometry& g, std::uint64_t seed) : geometry_(g) {
  rx_ = g.r_x();
  ry_ = g.r_y();
  c_ = g.c();
  inv_rx_ = 1 / rx_;
  inv_ry_ = 1 / ry_;
  inv_c_ = 1 / c_;
  spheres_ = rx_ == ry_ && ry_ == c_;
  side_ = g.tile * g.radius;
  side_x_ = side_ * inv_rx_;
  side_y_ = side_ * inv_ry_;
  if (side_x_ <= 2 || side_y_ <= 2)
    throw std::invalid_argument("micrograin tile must be wider than two grain diameters");
  // Poisson process of unit-space density rho' = -ln(1 - tau0)/pi (Eq. 13).
  Rng rng(seed);
  const std::uint64_t n = rng.poisson(g.unit_density() * side_x_ * side_y_);
  // Centres are floats, so Embree's vertex buffer holds them exactly and a hit
  // on a grain (not a ghost copy) needs no other record (see finish).
  auto coordinate = [&](double side) {
    float x = static_cast<float>(rng.uniform() * side);
    while (!(x < side)) x = std::nextafter(x, 0.0f);
    return static_cast<double>(x);
  };
  centres_.resize(n);
  for (auto& p : centres_) p = {coordinate(side_x_), coordinate(side_y_), 0.0};
  build_grid();
  build_scene();
}

MicrograinField::~MicrograinField() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void MicrograinField::build_grid() {
  // Cells of about one unit radius, at most 2048 per side.
  grid_nx_ = std::max(1, std::min(2048, static_cast<int>(side_x_)));
  grid_ny_ = std::max(1, std::min(2048, static_cast<int>(side_y_)));
  cell_x_ = side_x_ / grid_nx_;
  cell_y_ = side_y_ / grid_ny_;
  const std::size_t cells = static_cast<std::size_t>(grid_nx_) * grid_ny_;
  cell_start_.assign(cells + 1, 0);
  auto cell_of = [&](const Vec3& p) {
    const int ix = std::min(grid_nx_ - 1, static_cast<int>(p.x / cell_x_));
    const int iy = std::min(grid_ny_ - 1, static_cast<int>(p.y / cell_y_));
    return static_cast<std::size_t>(iy) * grid_nx_ + ix;
  };
  for (const Vec3& p : centres_) ++cell_start_[cell_of(p) + 1];
  for (std::size_t i = 0; i < cells; ++i) cell_start_[i + 1] += cell_start_[i];
  cell_items_.resize(centres_.size());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t k = 0; k < centres_.size(); ++k) cell_items_[fill[cell_of(centres_[k])]++] = static_cast<std::uint32_t>(k);
}

void MicrograinField::build_scene() {
  // The grains (primitive k = grain k), then ghost copies of those that
  // overlap the tile across a side, so that every grain meeting the tile's
  // column is present inside it.
  for (std::size_t k = 0; k < centres_.size(); ++k) prims_.push_back({centres_[k], static_cast<std::uint32_t>(k)});
  for (std::size_t k = 0; k < centres_.size(); ++k) {
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy) {
        const Vec3 p{centres_[k].x + sx * side_x_, centres_[k].y + sy * side_y_, 0.0};
        if ((sx != 0 || sy != 0) && p.x > -1 && p.x < side_x_ + 1 && p.y > -1 && p.y < side_y_ + 1) {
          prims_.push_back({p, static_cast<std::uint32_t>(k)});
        }
      }
  }
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree device creation failed");
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  if (!prims_.empty()) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), prims_.size()));
    vertices_ = v;
    for (std::size_t i = 0; i < prims_.size(); ++i) {
      v[4 * i + 0] = static_cast<float>(prims_[i].centre.x);
      v[4 * i + 1] = static_cast<float>(prims_[i].centre.y);
      v[4 * i + 2] = 0.0f;
      v[4 * i + 3] = 1.0f;
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(scene_);
}

Hit MicrograinField::intersect(Vec3 origin, Vec3 direction) const {
  const Vec3 d{direction.x * inv_rx_, direction.y * inv_ry_, direction.z * inv_c_};
  return intersect_unit(to_unit(origin), d);
}

Hit MicrograinField::intersect_unit(Vec3 o, Vec3 d) const { return trace<true>(o, d, kNoGrain); }

Hit MicrograinField::intersect_unit(Vec3 o, Vec3 d, std::uint32_t start_grain) const {
  return trace<true>(o, d, start_grain);
}

Hit::Kind MicrograinField::first_hit_kind_unit(Vec3 o, Vec3 d) const { return trace<false>(o, d, kNoGrain).kind; }

bool MicrograinField::occluded_unit(Vec3 o, Vec3 d, std::uint32_t start_grain) const {
  return trace<false>(o, d, start_grain).kind != Hit::Kind::Escape;
}

namespace {
// The Embree ray of a LoggedRay-like call, reset to "no hit yet".
void set_ray(RTCRayHit& rh, float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar) {
  rh.ray.org_x = ox;
  rh.ray.org_y = oy;
  rh.ray.org_z = oz;
  rh.ray.tnear = tnear;
  rh.ray.dir_x = dx;
  rh.ray.dir_y = dy;
  rh.ray.dir_z = dz;
  rh.ray.time = 0;
  rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Out of line: the hot loop keeps only the test of t_ray_log.
[[gnu::noinline]] void log_ray(const TraceSegment& s) {
  const RTCRay& r = s.rh.ray;
  t_ray_log->push_back({{r.org_x, r.org_y, r.org_z}, {r.dir_x, r.dir_y, r.dir_z}, r.tnear, s.tfar, s.o, s.leaving});
}
}  // namespace

void MicrograinField::call_embree(RTCRayHit& rh, const Vec3& origin, std::uint32_t leaving) const {
  LeavingContext context;
  rtcInitIntersectContext(&context);
  if (leaving != kNoGrain) {
    context.filter = reject_self_hit;
    context.prims = prims_.data();
    context.origin = &origin;
    context.leaving = leaving;
  }
  rtcIntersect1(scene_, &context, &rh);
}

void MicrograinField::embree_intersect(const LoggedRay& r, RTCRayHit& rh) const {
  set_ray(rh, r.org[0], r.org[1], r.org[2], r.dir[0], r.dir[1], r.dir[2], r.tnear, r.tfar);
  call_embree(rh, r.origin, r.leaving);
}

// kDetail = false fills only the kind and t of the hit: no normals, no position.
// Every field is given at once: zero-filling the large Hit first costs time.
// Always inlined into the trace: the call and the copy of the Hit cost time.
template <bool kDetail>
[[gnu::always_inline]] inline Hit MicrograinField::make_hit(Hit::Kind kind, double t, Vec3 p, Vec3 unit_normal,
                                                           std::uint32_t grain) const {
  if constexpr (kDetail) {
    const Vec3 up = wrap_unit(p);
    // Spherical grains: the unit normal (unit length up to rounding) is the real one.
    const Vec3 normal = !spheres_ && kind == Hit::Kind::Grain ? normal_from_unit(unit_normal) : unit_normal;
    return {kind, t, from_unit(up), up, normal, unit_normal, grain};
  } else {
    Hit hit;
    hit.kind = kind;
    hit.t = t;
    return hit;
  }
}

// Inlined into the trace (its first segment, on every ray); the segments
// after a side come from wrap_segment, out of line, so that the hot loop holds
// one copy. Measured (bench_micrograin_transport walk): about 2 points less
// walk overhead than out of line everywhere; inlined at both calls, 5 more.
[[gnu::always_inline]] inline TraceSegment MicrograinField::segment(Vec3 o, Vec3 d, double a, double inv_a,
                                                                    std::uint32_t start_grain, int wraps,
                                                                    double travelled) const {
  TraceSegment s;
  s.o = o;
  s.d = d;
  s.a = a;
  s.inv_a = inv_a;
  s.wraps = wraps;
  s.travelled = travelled;
  // Above every grain, going up: no ray needed (o.z first: nearly always
  // false, so well predicted, unlike the random sign of d.z).
  s.escape = o.z >= 1 && d.z >= 0;
  if (s.escape) return s;
  // Distances to the side, base or top ahead. The plane ahead is picked by
  // copysign, not by branches on the signs of d (random: mispredicted half
  // of the time): h + copysign(h, d) is exactly 2h or 0.
  auto ahead = [](double half, double d) { return half + std::copysign(half, d); };
  s.tz = d.z != 0 ? (ahead(0.5, d.z) - o.z) / d.z : kInf;
  s.up = d.z > 0;
  // Self-hits only on the first segment: after a wrap the ray may meet
  // its start grain again through the periodic tile.
  s.leaving = wraps == 0 ? start_grain : kNoGrain;
  // Embree's tfar is the base or top only; a hit past a side is discarded
  // after the call (finish). So the sides' divisions are not on the way
  // from the last hit to this call.
  s.tfar = static_cast<float>(s.tz) * (1.0f + 1e-6f);
  set_ray(s.rh, static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z), static_cast<float>(d.x),
          static_cast<float>(d.y), static_cast<float>(d.z), 0.0f, s.tfar);
  s.tx = d.x != 0 ? (ahead(0.5 * side_x_, d.x) - o.x) / d.x : kInf;
  s.ty = d.y != 0 ? (ahead(0.5 * side_y_, d.y) - o.y) / d.y : kInf;
  s.t_side = std::min(s.tx, s.ty);
  s.side_far = static_cast<float>(s.t_side) * (1.0f + 1e-6f);
  if (t_ray_log) log_ray(s);
  return s;
}

[[gnu::noinline]] TraceSegment MicrograinField::wrap_segment(Vec3 o, Vec3 d, double a, double inv_a, int wraps,
                                                             double travelled) const {
  return segment(o, d, a, inv_a, kNoGrain, wraps, travelled);
}

template <bool kDetail>
Hit MicrograinField::trace(Vec3 o, Vec3 d, std::uint32_t start_grain) const {
  const double a = dot(d, d);  // of the sphere roots
  TraceSegment s = segment(wrap_unit(o), d, a, 1 / a, start_grain, 0, 0.0);
  if (!s.escape) call_embree(s.rh, s.o, s.leaving);
  return finish<kDetail>(s);
}

template <bool kDetail>
Hit MicrograinField::finish(const TraceSegment& first) const {
  // Usually the first answer decides; later segments (after a spurious hit
  // or across a side) live in `next`, so the common case copies nothing.
  const TraceSegment* s = &first;
  TraceSegment next;
  while (!s->escape) {
    const RTCRayHit* rh = &s->rh;
    if (rh->hit.geomID != RTC_INVALID_GEOMETRY_ID && rh->ray.tfar <= s->side_far) {
      // Exact root in double precision for the sphere Embree found.
      // A grain's centre is exact in Embree's vertex buffer, which Embree has
      // just read (in the L1 cache, unlike prims_); a ghost's is in prims_.
      const std::uint32_t id = rh->hit.primID;
      const bool ghost = id >= centres_.size();
      const float* v = vertices_ + 4 * static_cast<std::size_t>(id);
      const Vec3 c = ghost ? prims_[id].centre : Vec3{v[0], v[1], 0.0};
      const std::uint32_t owner = ghost ? prims_[id].owner : id;
      const Vec3 oc = s->o - c;
      const double b = dot(oc, s->d), cc = dot(oc, oc) - 1;
      const double disc = b * b - s->a * cc;
      const double sq = disc < 0 ? 0 : std::sqrt(disc);
      const double t0 = (-b - sq) * s->inv_a, t1 = (-b + sq) * s->inv_a;
      if (disc < 0 || t1 <= 0) {
        // A spurious hit: Embree grazes a sphere that the double-precision
        // root misses, or one behind the origin (a float artefact). Step
        // past it by kSkip (unit space, ~1e-4 grain radius): an ulp-sized
        // step could crawl for ages.
        const float t_near = rh->ray.tfar + kSkip * static_cast<float>(std::sqrt(s->inv_a));  // kSkip / |d|
        if (s != &next) next = *s;
        const RTCRay& r = next.rh.ray;
        set_ray(next.rh, r.org_x, r.org_y, r.org_z, r.dir_x, r.dir_y, r.dir_z, t_near, next.tfar);
        if (t_ray_log) log_ray(next);
        call_embree(next.rh, next.o, next.leaving);
        s = &next;
        continue;
      }
      const double tf = rh->ray.tfar;
      const double t = (t0 >= 0 && std::fabs(t0 - tf) <= std::fabs(t1 - tf)) ? t0 : t1;
      // A root beyond the base plane is on the lower half: the ray meets the
      // base first. (t < tz is tested first: nearly always true, so well
      // predicted, unlike the random `up`.)
      if (t < s->tz || s->up) {
        const Vec3 p = s->o + s->d * t;
        // The unit normal is p - c, unit length up to rounding: p is on the unit sphere.
        return make_hit<kDetail>(Hit::Kind::Grain, s->travelled + t, p, p - c, owner);
      }
    }
    if (s->tz <= s->t_side && !s->up) {
      Vec3 p = s->o + s->d * s->tz;
      p.z = 0;
      return make_hit<kDetail>(Hit::Kind::Base, s->travelled + s->tz, p, {0, 0, 1}, kNoGrain);
    }
    if (s->tz <= s->t_side || s->wraps + 1 >= kMaxWraps) break;  // the top: escape
    // Leave the tile through a side and re-enter from the opposite one.
    Vec3 o = s->o + s->d * s->t_side;
    // (No wrap_unit here: it would map side_x back to 0 and stall the ray.)
    if (s->tx <= s->ty) o.x = s->d.x > 0 ? 0 : side_x_;
    if (s->ty <= s->tx) o.y = s->d.y > 0 ? 0 : side_y_;
    next = wrap_segment(o, s->d, s->a, s->inv_a, s->wraps + 1, s->travelled + s->t_side);
    if (!next.escape) call_embree(next.rh, next.o, next.leaving);
    s = &next;
  }
  return Hit{};  // escape
}

void MicrograinField::first_hits_unit(const Vec3* origins, std::size_t n, Vec3 d, Hit::Kind* kinds,
                                      Vec3* normals) const {
  if (normals)
    trace_packets<true>(origins, n, d, kinds, normals);
  else
    trace_packets<false>(origins, n, d, kinds, nullptr);
}

// Flattened: finish and make_hit inlined here (not in the single-ray trace,
// whose code layout the walk is tuned to), so that the fields of the Hit that
// are not kept are not computed.
template <bool kDetail>
[[gnu::flatten]] void MicrograinField::trace_packets(const Vec3* origins, std::size_t n, Vec3 d, Hit::Kind* kinds,
                                    Vec3* normals) const {
  constexpr int kLanes = 16;
  thread_local std::vector<std::uint32_t> order, scratch;
  thread_local std::vector<Vec3> sorted;
  packet_order(origins, n, side_x_, side_y_, kPacketOriginsPerCell, order, sorted, scratch);
  const double a = dot(d, d), inv_a = 1 / a;
  TraceSegment s[kLanes];  // (built in place: a copy reads back stores in pieces, see TraceSegment)
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[kLanes];
  for (std::size_t i = 0; i < n; i += kLanes) {
    const int m = static_cast<int>(std::min<std::size_t>(kLanes, n - i));
    for (int k = 0; k < kLanes; ++k) {
      valid[k] = 0;
      if (k >= m) continue;
      ::new (&s[k]) TraceSegment(segment(wrap_unit(sorted[i + k]), d, a, inv_a, kNoGrain, 0, 0.0));
      if (s[k].escape) continue;
      valid[k] = -1;
      const RTCRay& r = s[k].rh.ray;
      rh.ray.org_x[k] = r.org_x;
      rh.ray.org_y[k] = r.org_y;
      rh.ray.org_z[k] = r.org_z;
      rh.ray.dir_x[k] = r.dir_x;
      rh.ray.dir_y[k] = r.dir_y;
      rh.ray.dir_z[k] = r.dir_z;
      rh.ray.tnear[k] = r.tnear;
      rh.ray.tfar[k] = r.tfar;
      rh.ray.time[k] = 0;
      rh.ray.mask[k] = 0xFFFFFFFFu;
      rh.ray.id[k] = 0;
      rh.ray.flags[k] = 0;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect16(valid, scene_, &context, &rh);
    for (int k = 0; k < m; ++k) {
      s[k].rh.ray.tfar = rh.ray.tfar[k];
      s[k].rh.hit.geomID = rh.hit.geomID[k];
      s[k].rh.hit.primID = rh.hit.primID[k];
      const Hit h = finish<kDetail>(s[k]);
      kinds[order[i + k]] = h.kind;
      if constexpr (kDetail) normals[order[i + k]] = h.normal;
    }
  }
}

// Visits the grains within unit-space distance `reach` of (x, y), periodic,
// until fn(k, d2) returns true; returns whether it did.
template <class Fn>
bool MicrograinField::visit_grains_near(double x, double y, double reach, Fn&& fn) const {
  const int ix0 = static_cast<int>(std::floor((x - reach) / cell_x_));
  const int ix1 = static_cast<int>(std::floor((x + reach) / cell_x_));
  const int iy0 = static_cast<int>(std::floor((y - reach) / cell_y_));
  const int iy1 = static_cast<int>(std::floor((y + reach) / cell_y_));
  const int nx = std::min(ix1 - ix0 + 1, grid_nx_), ny = std::min(iy1 - iy0 + 1, grid_ny_);
  const double r2 = reach * reach;
  for (int jy = 0; jy < ny; ++jy) {
    const int cy = ((iy0 + jy) % grid_ny_ + grid_ny_) % grid_ny_;
    for (int jx = 0; jx < nx; ++jx) {
      const int cx = ((ix0 + jx) % grid_nx_ + grid_nx_) % grid_nx_;
      const std::size_t cell = static_cast<std::size_t>(cy) * grid_nx_ + cx;
      for (std::uint32_t s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s) {
        const std::uint32_t k = cell_items_[s];
        double dx = x - centres_[k].x, dy = y - centres_[k].y;
        dx -= side_x_ * std::round(dx / side_x_);
        dy -= side_y_ * std::round(dy / side_y_);
        const double d2 = dx * dx + dy * dy;
        if (d2 <= r2 && fn(k, d2)) return true;
      }
    }
  }
  return false;
}

bool MicrograinField::under_grain(double x, double y) const {
  return visit_grains_near(x, y, 1.0, [](std::size_t, double d2) { return d2 < 1.0; });
}

double MicrograinField::nearest_centre_distance(double x, double y) const {
  if (centres_.empty()) return kInf;
  double best2 = kInf;
  const double half_diagonal = 0.5 * std::hypot(side_x_, side_y_);
  for (double reach = std::max(cell_x_, cell_y_);; reach *= 2) {
    reach = std::min(reach, half_diagonal);
    visit_grains_near(x, y, reach, [&](std::size_t, double d2) {
      best2 = std::min(best2, d2);
      return false;
    });
    if (best2 <= reach * reach || reach >= half_diagonal) return std::sqrt(best2);
  }
}

bool MicrograinField::inside_other_grain(Vec3 p, std::size_t except) const {
  return visit_grains_near(p.x, p.y, 1.0, [&](std::size_t k, double d2) { return k != except && d2 + p.z * p.z < 1.0; });
}

}  // namespace mcref
