#include "sim/geometry/micrograin_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sim/core/rng.h"
#include "sim/geometry/ray_log.h"

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
  const Vec3* prim_centres;
  const std::uint32_t* owner;
  const LoggedRay* ray;
};

void reject_self_hit(const RTCFilterFunctionNArguments* args) {
  const auto* c = static_cast<const LeavingContext*>(args->context);
  const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, 0);
  if (c->owner[prim] != c->ray->leaving) return;
  const Vec3 oc = c->ray->origin - c->prim_centres[prim];  // the copy the origin lies on, not a ghost
  if (std::fabs(dot(oc, oc) - 1) < 1e-6) args->valid[0] = 0;
}
}  // namespace

double MicrograinGeometry::c() const { return radius * std::sqrt(beta_x * beta_y); }
double MicrograinGeometry::r_x() const { return c() / beta_x; }
double MicrograinGeometry::r_y() const { return c() / beta_y; }
double MicrograinGeometry::density() const { return unit_density() / (r_x() * r_y()); }
double MicrograinGeometry::unit_density() const { return -std::log1p(-tau0) / kPi; }

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
  centres_.resize(n);
  for (auto& p : centres_) p = {rng.uniform() * side_x_, rng.uniform() * side_y_, 0.0};
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
  // Ghost copies of the grains that overlap the tile across a side, so that
  // every grain meeting the tile's column is present inside it.
  for (std::size_t k = 0; k < centres_.size(); ++k) {
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy) {
        const Vec3 p{centres_[k].x + sx * side_x_, centres_[k].y + sy * side_y_, 0.0};
        if (p.x > -1 && p.x < side_x_ + 1 && p.y > -1 && p.y < side_y_ + 1) {
          prim_centres_.push_back(p);
          owner_.push_back(static_cast<std::uint32_t>(k));
        }
      }
  }
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree device creation failed");
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  if (!prim_centres_.empty()) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), prim_centres_.size()));
    for (std::size_t i = 0; i < prim_centres_.size(); ++i) {
      v[4 * i + 0] = static_cast<float>(prim_centres_[i].x);
      v[4 * i + 1] = static_cast<float>(prim_centres_[i].y);
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

void MicrograinField::embree_intersect(const LoggedRay& r, RTCRayHit& rh) const {
  rh.ray.org_x = r.org[0];
  rh.ray.org_y = r.org[1];
  rh.ray.org_z = r.org[2];
  rh.ray.dir_x = r.dir[0];
  rh.ray.dir_y = r.dir[1];
  rh.ray.dir_z = r.dir[2];
  rh.ray.tnear = r.tnear;
  rh.ray.tfar = r.tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.ray.time = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  LeavingContext context;
  rtcInitIntersectContext(&context);
  if (r.leaving != kNoGrain) {
    context.filter = reject_self_hit;
    context.prim_centres = prim_centres_.data();
    context.owner = owner_.data();
    context.ray = &r;
  }
  rtcIntersect1(scene_, &context, &rh);
}

// kDetail = false fills only the kind and t of the hit: no normals, no position.
// Every field is given at once: zero-filling the large Hit first costs time.
template <bool kDetail>
Hit MicrograinField::make_hit(Hit::Kind kind, double t, Vec3 p, Vec3 unit_normal, std::uint32_t grain) const {
  if constexpr (kDetail) {
    const Vec3 up = wrap_unit(p);
    // Spherical grains: the unit normal (unit length up to rounding) is the real one.
    const Vec3 normal = kind == Hit::Kind::Grain && !spheres_ ? normal_from_unit(unit_normal) : unit_normal;
    return {kind, t, from_unit(up), up, normal, unit_normal, grain};
  } else {
    Hit hit;
    hit.kind = kind;
    hit.t = t;
    return hit;
  }
}

template <bool kDetail>
Hit MicrograinField::trace(Vec3 o, Vec3 d, std::uint32_t start_grain) const {
  o = wrap_unit(o);
  const double a = dot(d, d), inv_a = 1 / a;  // of the sphere roots below
  double travelled = 0;
  for (int wraps = 0; wraps < kMaxWraps; ++wraps) {
    if (d.z >= 0 && o.z >= 1) break;  // above every grain, going up: escape
    const double tx = d.x > 0 ? (side_x_ - o.x) / d.x : (d.x < 0 ? -o.x / d.x : kInf);
    const double ty = d.y > 0 ? (side_y_ - o.y) / d.y : (d.y < 0 ? -o.y / d.y : kInf);
    const double t_side = std::min(tx, ty);
    const double t_base = d.z < 0 ? -o.z / d.z : kInf;
    const double t_top = d.z > 0 ? (1 - o.z) / d.z : kInf;
    const double t_far = std::min(t_side, std::min(t_base, t_top));

    float t_near = 0.0f;
    for (;;) {
      // Self-hits only on the first segment: after a wrap the ray may meet
      // its start grain again through the periodic tile.
      const LoggedRay r{{static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z)},
                        {static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                        t_near,
                        static_cast<float>(t_far) * (1.0f + 1e-6f),
                        o,
                        wraps == 0 ? start_grain : kNoGrain};
      if (t_ray_log) t_ray_log->push_back(r);
      RTCRayHit rh;
      embree_intersect(r, rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      // Exact root in double precision for the sphere Embree found.
      const Vec3 c = prim_centres_[rh.hit.primID];
      const Vec3 oc = o - c;
      const double b = dot(oc, d), cc = dot(oc, oc) - 1;
      const double disc = b * b - a * cc;
      if (disc < 0) {
        // A spurious hit: Embree grazes a sphere that the double-precision
        // root misses. Step past it by kSkip (unit space, ~1e-4 grain
        // radius): an ulp-sized step could crawl for ages.
        t_near = rh.ray.tfar + kSkip;
        continue;
      }
      const double sq = std::sqrt(disc);
      const double t0 = (-b - sq) * inv_a, t1 = (-b + sq) * inv_a;
      if (t1 <= 0) {  // the sphere lies behind the origin: a float artefact
        t_near = rh.ray.tfar + kSkip;
        continue;
      }
      const double t = (t0 >= 0 && std::fabs(t0 - rh.ray.tfar) <= std::fabs(t1 - rh.ray.tfar)) ? t0 : t1;
      if (t >= t_base) break;  // meets the base plane first (a lower-half hit)
      const Vec3 p = o + d * t;
      // The unit normal is p - c, unit length up to rounding: p is on the unit sphere.
      return make_hit<kDetail>(Hit::Kind::Grain, travelled + t, p, p - c, owner_[rh.hit.primID]);
    }
    if (t_far == t_base) {
      Vec3 p = o + d * t_base;
      p.z = 0;
      return make_hit<kDetail>(Hit::Kind::Base, travelled + t_base, p, {0, 0, 1}, 0);
    }
    if (t_far == t_top) break;
    // Leave the tile through a side and re-enter from the opposite one.
    o = o + d * t_side;
    travelled += t_side;
    // (No wrap_unit here: it would map side_x back to 0 and stall the ray.)
    if (tx <= ty) o.x = d.x > 0 ? 0 : side_x_;
    if (ty <= tx) o.y = d.y > 0 ? 0 : side_y_;
  }
  return Hit{};  // escape
}

void MicrograinField::for_grains_near(double x, double y, double reach,
                                      const std::function<void(std::size_t, double)>& fn) const {
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
        if (d2 <= r2) fn(k, d2);
      }
    }
  }
}

double MicrograinField::nearest_centre_distance(double x, double y) const {
  if (centres_.empty()) return kInf;
  double best2 = kInf;
  const double half_diagonal = 0.5 * std::hypot(side_x_, side_y_);
  for (double reach = std::max(cell_x_, cell_y_);; reach *= 2) {
    reach = std::min(reach, half_diagonal);
    for_grains_near(x, y, reach, [&](std::size_t, double d2) { best2 = std::min(best2, d2); });
    if (best2 <= reach * reach || reach >= half_diagonal) return std::sqrt(best2);
  }
}

bool MicrograinField::inside_other_grain(Vec3 p, std::size_t except) const {
  bool inside = false;
  for_grains_near(p.x, p.y, 1.0, [&](std::size_t k, double d2) {
    if (k != except && d2 + p.z * p.z < 1.0) inside = true;
  });
  return inside;
}

}  // namespace mcref
