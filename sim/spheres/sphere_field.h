#pragma once
// Unit spheres (r = 1) in Embree, periodic laterally with period `tile`:
// exact first hits along rays (Embree sphere points find the sphere, the
// root is refined in double precision), rays wrap at the tile's sides.
//
// Precision: the slab is cut into depth layers of `layer_height` radii, each
// its own Embree scene in local coordinates (origin at the layer's mid-depth),
// so float z stays below ~layer_height even in slabs 10^4 radii deep; x, y
// stay below the tile (at most 1000 radii, spheres_config.cpp).
// A sphere that crosses a layer boundary is in both layers. Spheres near a
// tile side have ghost copies across it.
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

struct SphereHit {
  enum class Kind { Escape, Transmit, Sphere };
  Kind kind = Kind::Escape;  // Escape: leaves through the top; Transmit: below every sphere
  double t = 0;              // distance travelled (unit direction)
  Vec3 position;             // wrapped into the tile
  Vec3 normal;               // outward unit normal of the sphere hit
  std::uint32_t sphere = 0;  // index of the (real) sphere hit
};

class SphereField {
 public:
  static constexpr std::uint32_t kNoSphere = 0xFFFFFFFFu;

  // centres: x, y in [0, tile), any z. tile > 2.
  SphereField(std::vector<Vec3> centres, double tile, double layer_height = 1024.0);
  ~SphereField();
  SphereField(const SphereField&) = delete;
  SphereField& operator=(const SphereField&) = delete;

  // First sphere hit by the ray (direction unit length). `start_sphere` is the
  // sphere the origin lies on (kNoSphere if none), so that it is not hit again.
  // The origin must lie outside every sphere.
  SphereHit trace(Vec3 origin, Vec3 direction, std::uint32_t start_sphere = kNoSphere) const;

  std::size_t sphere_count() const { return centres_.size(); }
  std::size_t primitive_count() const { return primitives_; }
  const std::vector<Vec3>& centres() const { return centres_; }
  double tile() const { return tile_; }
  double top() const { return top_; }        // highest point of any sphere (z)
  double bottom() const { return bottom_; }  // lowest point of any sphere (z)
  int layers() const { return static_cast<int>(layers_.size()); }
  // Bytes held by our arrays and Embree's vertex buffers (not its BVH).
  std::size_t array_bytes() const;
  // For benchmarks: the raw scene of a layer and its local z origin.
  RTCScene layer_scene(int k) const { return layers_[k].scene; }
  double layer_origin(int k) const { return layers_[k].z_origin; }
  // Layer holding height z (top layer above, bottom layer below the slab).
  int layer_of(double z) const;
  Vec3 wrap(Vec3 p) const;

 private:
  struct Layer {
    double z_lo, z_hi;  // z range of this layer (outermost layers unbounded)
    double z_origin;    // local origin of the Embree coordinates
    RTCScene scene = nullptr;
    std::vector<std::uint32_t> owner;  // primitive -> real sphere
    std::vector<Vec3> centre;          // primitive centres (global, ghosts included)
  };
  std::vector<Vec3> centres_;
  double tile_, top_ = 1, bottom_ = -1, height_;
  std::size_t primitives_ = 0;
  std::vector<Layer> layers_;
  RTCDevice device_ = nullptr;
};

}  // namespace mcref
