#pragma once
// A random micrograin field (LRPB23 Sec. 3): grain centres form a Poisson
// process on a square periodic tile of the plane z = 0 (unit-space
// coordinates rounded to float, exact in Embree's vertex buffer); every grain is the
// upper half (z >= 0) of an ellipsoid with horizontal semi-axes r_x, r_y and
// vertical semi-axis c. The base plane z = 0 lies below.
//
// Internally everything is traced in the "unit space" x/r_x, y/r_y, z/c, where
// grains are unit spheres (Embree sphere points, exact roots refined in double
// precision) and ray parameters t are the same as in real space. Rays wrap
// periodically at the tile's sides, so the field is infinite.
#include <embree3/rtcore.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/micrograin/micrograin_geometry.h"
#include "sim/micrograin/ray_log.h"

namespace mcref {

struct Hit {
  enum class Kind { Escape, Grain, Base };
  Kind kind = Kind::Escape;
  double t = 0;       // distance travelled along the (unit, real-space) direction
  Vec3 position;      // real space, wrapped into the tile
  Vec3 unit_position; // the same in unit space
  Vec3 normal;        // real-space unit normal (grain: ellipsoid normal; base: +z)
  Vec3 unit_normal;   // unit-space normal (= unit-space position relative to the centre)
  std::uint32_t grain = 0;  // index of the grain (real, not a ghost copy); kNoGrain on the base
};

// An Embree primitive: a grain, or a ghost copy of it across a side of the
// tile; its exact unit-space centre and the index of the real grain, in one
// cache line (both are read together: by the self-hit filter, and after a hit
// on a ghost; a hit on a grain reads Embree's vertex buffer instead).
struct alignas(32) GrainCopy {
  Vec3 centre;
  std::uint32_t owner;
};

struct TraceSegment;  // one straight piece of a trace (micrograin_field.cpp)

class MicrograinField {
 public:
  // Builds one realization of the field from its own seed.
  MicrograinField(const MicrograinGeometry& geometry, std::uint64_t seed);
  ~MicrograinField();
  MicrograinField(const MicrograinField&) = delete;
  MicrograinField& operator=(const MicrograinField&) = delete;

  const MicrograinGeometry& geometry() const { return geometry_; }
  std::size_t grain_count() const { return centres_.size(); }
  // Unit-space centre (z = 0) of grain k.
  Vec3 unit_centre(std::size_t k) const { return centres_[k]; }
  // Tile side in real units and in unit space.
  double tile_side() const { return side_; }
  double unit_side_x() const { return side_x_; }
  double unit_side_y() const { return side_y_; }

  // First surface hit along a ray (real space; `direction` unit length).
  Hit intersect(Vec3 origin, Vec3 direction) const;
  // Same, with origin and direction already in unit space (hot path for
  // estimators; the direction need not be unit length, t is in its units).
  Hit intersect_unit(Vec3 unit_origin, Vec3 unit_direction) const;
  // Same, for a ray leaving the surface of grain `start_grain` (not hit again).
  Hit intersect_unit(Vec3 unit_origin, Vec3 unit_direction, std::uint32_t start_grain) const;
  // Only the kind of the first hit (cheaper: no normal or position).
  Hit::Kind first_hit_kind_unit(Vec3 unit_origin, Vec3 unit_direction) const;
  // First hits of rays from many unit-space origins along one unit-space
  // direction d (not from a grain), the same as first_hit_kind_unit and
  // intersect_unit one by one: kinds[k] and, if `normals` is given, the real-space
  // normal normals[k] of origin k. Traced in packets of 16 nearby origins
  // (rtcIntersect16 on rays sorted by packet_order; any later segment one by one).
  void first_hits_unit(const Vec3* origins, std::size_t n, Vec3 d, Hit::Kind* kinds, Vec3* normals = nullptr) const;
  // True if a ray from a unit-space point meets a grain or the base before
  // leaving the grain layer. `start_grain` is the grain the point lies on
  // (kNoGrain for a point on the base), so that it is not hit again.
  bool occluded_unit(Vec3 unit_origin, Vec3 unit_direction, std::uint32_t start_grain) const;
  static constexpr std::uint32_t kNoGrain = 0xFFFFFFFFu;

  // Periodic unit-space distance from (x, y) to the closest centre
  // (infinity if the tile holds no grain).
  double nearest_centre_distance(double x, double y) const;
  // True if the unit-space point (x, y) of the base lies under a grain: closer
  // than 1 to a centre (periodic). Stops at the first such grain.
  bool under_grain(double x, double y) const;
  // True if the unit-space point p lies strictly inside a grain other than `except`.
  bool inside_other_grain(Vec3 p, std::size_t except) const;

  Vec3 to_unit(Vec3 p) const { return {p.x * inv_rx_, p.y * inv_ry_, p.z * inv_c_}; }
  Vec3 from_unit(Vec3 p) const { return {p.x * rx_, p.y * ry_, p.z * c_}; }
  // Real-space normal from a unit-space one (inverse transpose of the map).
  Vec3 normal_from_unit(Vec3 n) const {
    const Vec3 m{n.x * inv_rx_, n.y * inv_ry_, n.z * inv_c_};
    return m * (1 / std::sqrt(dot(m, m)));
  }
  // Wraps a unit-space point into [0, side_x) x [0, side_y).
  Vec3 wrap_unit(Vec3 p) const {
    // Most points are already inside: a compare, no division.
    if (!(p.x >= 0 && p.x < side_x_)) {
      p.x -= side_x_ * std::floor(p.x / side_x_);
      if (p.x >= side_x_) p.x -= side_x_;  // floor rounding at the upper edge
    }
    if (!(p.y >= 0 && p.y < side_y_)) {
      p.y -= side_y_ * std::floor(p.y / side_y_);
      if (p.y >= side_y_) p.y -= side_y_;
    }
    return p;
  }

  // Raw Embree handles, for benchmarks that compare with bare rtcIntersect1.
  RTCScene embree_scene() const { return scene_; }
  // One rtcIntersect1 call as the tracer makes it (with its self-hit filter
  // for a ray leaving a grain); benchmarks replay ray logs through it.
  void embree_intersect(const LoggedRay& ray, RTCRayHit& rh) const;

 private:
  void build_grid();
  // Calls fn(k, d2) for the grains within unit-space distance `reach` of (x, y)
  // (periodic; d2 the squared distance) until it returns true; returns whether it did.
  template <class Fn>
  bool visit_grains_near(double x, double y, double reach, Fn&& fn) const;
  void build_scene();
  template <bool kDetail>
  Hit make_hit(Hit::Kind kind, double t, Vec3 unit_position, Vec3 unit_normal, std::uint32_t grain) const;
  template <bool kDetail>
  Hit trace(Vec3 unit_origin, Vec3 unit_direction, std::uint32_t start_grain) const;
  // The segment from o along d (a = d . d) after `wraps` sides and `travelled`.
  TraceSegment segment(Vec3 o, Vec3 d, double a, double inv_a, std::uint32_t start_grain, int wraps,
                       double travelled) const;
  // The same for the segment after a side (no start grain), out of line.
  TraceSegment wrap_segment(Vec3 o, Vec3 d, double a, double inv_a, int wraps, double travelled) const;
  // rtcIntersect1 on a prepared ray, with the self-hit filter if it leaves
  // grain `leaving` (not kNoGrain) from the exact unit-space point `origin`.
  void call_embree(RTCRayHit& rh, const Vec3& origin, std::uint32_t leaving) const;
  // The hit of a trace from its first segment with Embree's answer in it
  // (calls Embree again after a spurious hit and across the tile's sides).
  template <bool kDetail>
  Hit finish(const TraceSegment& s) const;
  template <bool kDetail>
  [[gnu::flatten]] void trace_packets(const Vec3* origins, std::size_t n, Vec3 d, Hit::Kind* kinds, Vec3* normals) const;

  MicrograinGeometry geometry_;
  double rx_, ry_, c_, inv_rx_, inv_ry_, inv_c_;
  bool spheres_;  // r_x = r_y = c: grains are spheres in real space too
  double side_, side_x_, side_y_;
  std::vector<Vec3> centres_;          // real grains, unit space
  std::vector<GrainCopy> prims_;  // Embree primitive -> its grain copy (grains first, then ghosts)
  const float* vertices_ = nullptr;  // Embree's vertex buffer (x, y, z, radius per primitive)
  // Uniform grid over the unit tile for neighbour queries.
  int grid_nx_ = 1, grid_ny_ = 1;
  double cell_x_ = 1, cell_y_ = 1;
  std::vector<std::uint32_t> cell_start_, cell_items_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace mcref
