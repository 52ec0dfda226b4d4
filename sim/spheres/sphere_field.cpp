#include "sim/spheres/sphere_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mcref {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// A ray that crosses this many tile sides or layer boundaries without a hit
// travels (numerically) horizontally through empty space; it is reported as
// escaping (measure zero for random directions).
constexpr int kMaxSegments = 1 << 20;
// Step past a spurious hit (local float units, ~1e-4 radius).
constexpr float kSkip = 1e-4f;
}  // namespace

SphereField::SphereField(std::vector<Vec3> centres, double tile, double layer_height)
    : centres_(std::move(centres)), tile_(tile), height_(layer_height) {
  if (tile_ <= 2) throw std::invalid_argument("sphere tile must be wider than one diameter");
  if (!centres_.empty()) {
    double zmax = -kInf, zmin = kInf;
    for (const Vec3& c : centres_) {
      zmax = std::max(zmax, c.z);
      zmin = std::min(zmin, c.z);
    }
    top_ = zmax + 1;
    bottom_ = zmin - 1;
  }
  // Layers below the top: [top - (k+1) H, top - k H]; the first is open above,
  // the last open below.
  const int n = std::max(1, static_cast<int>(std::ceil((top_ - bottom_) / height_)));
  layers_.resize(n);
  for (int k = 0; k < n; ++k) {
    Layer& L = layers_[k];
    L.z_hi = k == 0 ? kInf : top_ - k * height_;
    L.z_lo = k == n - 1 ? -kInf : top_ - (k + 1) * height_;
    L.z_origin = top_ - (k + 0.5) * height_;
  }
  for (std::size_t i = 0; i < centres_.size(); ++i) {
    const Vec3& c = centres_[i];
    const int k0 = layer_of(c.z + 1), k1 = layer_of(c.z - 1);
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy) {
        const Vec3 p{c.x + sx * tile_, c.y + sy * tile_, c.z};
        if (p.x <= -1 || p.x >= tile_ + 1 || p.y <= -1 || p.y >= tile_ + 1) continue;
        for (int k = k0; k <= k1; ++k) {
          layers_[k].centre.push_back(p);
          layers_[k].owner.push_back(static_cast<std::uint32_t>(i));
        }
      }
  }
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree device creation failed");
  for (Layer& L : layers_) {
    L.scene = rtcNewScene(device_);
    rtcSetSceneBuildQuality(L.scene, RTC_BUILD_QUALITY_HIGH);
    primitives_ += L.centre.size();
    if (!L.centre.empty()) {
      RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                            4 * sizeof(float), L.centre.size()));
      for (std::size_t i = 0; i < L.centre.size(); ++i) {
        v[4 * i + 0] = static_cast<float>(L.centre[i].x);
        v[4 * i + 1] = static_cast<float>(L.centre[i].y);
        v[4 * i + 2] = static_cast<float>(L.centre[i].z - L.z_origin);
        v[4 * i + 3] = 1.0f;
      }
      rtcCommitGeometry(geom);
      rtcAttachGeometry(L.scene, geom);
      rtcReleaseGeometry(geom);
    }
    rtcCommitScene(L.scene);
  }
}

SphereField::~SphereField() {
  for (Layer& L : layers_)
    if (L.scene) rtcReleaseScene(L.scene);
  if (device_) rtcReleaseDevice(device_);
}

std::size_t SphereField::array_bytes() const {
  std::size_t b = centres_.size() * sizeof(Vec3);
  for (const Layer& L : layers_) b += L.centre.size() * (sizeof(Vec3) + sizeof(std::uint32_t) + 4 * sizeof(float));
  return b;
}

int SphereField::layer_of(double z) const {
  const int n = static_cast<int>(layers_.size());
  const int k = static_cast<int>(std::floor((top_ - z) / height_));
  return std::clamp(k, 0, n - 1);
}

Vec3 SphereField::wrap(Vec3 p) const {
  p.x -= tile_ * std::floor(p.x / tile_);
  p.y -= tile_ * std::floor(p.y / tile_);
  if (p.x >= tile_) p.x -= tile_;
  if (p.y >= tile_) p.y -= tile_;
  return p;
}

SphereHit SphereField::trace(Vec3 o, Vec3 d, std::uint32_t start_sphere) const {
  SphereHit hit;
  o = wrap(o);
  int k = layer_of(o.z);
  double travelled = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int segment = 0; segment < kMaxSegments; ++segment) {
    if (d.z >= 0 && o.z >= top_) break;  // above every sphere, going up: escape
    if (d.z <= 0 && o.z <= bottom_) {    // below every sphere, going down
      hit.kind = SphereHit::Kind::Transmit;
      hit.t = travelled;
      hit.position = o;
      return hit;
    }
    const Layer& L = layers_[k];
    const double tx = d.x > 0 ? (tile_ - o.x) / d.x : (d.x < 0 ? -o.x / d.x : kInf);
    const double ty = d.y > 0 ? (tile_ - o.y) / d.y : (d.y < 0 ? -o.y / d.y : kInf);
    const double t_side = std::min(tx, ty);
    // Leave the layer (or the slab: top_ / bottom_) through its z bounds.
    const double z_up = std::min(L.z_hi, top_), z_down = std::max(L.z_lo, bottom_);
    const double t_up = d.z > 0 ? (z_up - o.z) / d.z : kInf;
    const double t_down = d.z < 0 ? (z_down - o.z) / d.z : kInf;
    const double t_layer = std::min(t_up, t_down);
    const double t_far = std::max(0.0, std::min(t_side, t_layer));

    float t_near = 0.0f;
    for (;;) {
      RTCRayHit rh;
      rh.ray.org_x = static_cast<float>(o.x);
      rh.ray.org_y = static_cast<float>(o.y);
      rh.ray.org_z = static_cast<float>(o.z - L.z_origin);
      rh.ray.dir_x = static_cast<float>(d.x);
      rh.ray.dir_y = static_cast<float>(d.y);
      rh.ray.dir_z = static_cast<float>(d.z);
      rh.ray.tnear = t_near;
      rh.ray.tfar = static_cast<float>(t_far) * (1.0f + 1e-6f) + 1e-6f;
      rh.ray.mask = 0xFFFFFFFFu;
      rh.ray.flags = 0;
      rh.ray.time = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      if (rh.ray.tnear > rh.ray.tfar) break;
      rtcIntersect1(L.scene, &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      const Vec3 c = L.centre[rh.hit.primID];
      const Vec3 oc = o - c;
      const double b = dot(oc, d), cc = dot(oc, oc) - 1;
      const double disc = b * b - cc;
      const bool self = segment == 0 && L.owner[rh.hit.primID] == start_sphere && std::fabs(cc) < 1e-6;
      const double t0 = disc >= 0 ? -b - std::sqrt(disc) : 0;
      // Spurious: the start sphere again, a float graze the double root
      // misses, or an origin numerically inside a sphere (t0 < 0).
      if (self || disc < 0 || t0 < -1e-9) {
        t_near = rh.ray.tfar + kSkip;
        continue;
      }
      const double t = std::max(t0, 0.0);
      const Vec3 p = o + d * t;
      hit.kind = SphereHit::Kind::Sphere;
      hit.t = travelled + t;
      hit.sphere = L.owner[rh.hit.primID];
      hit.normal = normalize(p - c);
      hit.position = wrap(p);
      return hit;
    }
    // No hit in this segment: move to its end.
    o = o + d * t_far;
    travelled += t_far;
    if (t_side <= t_layer) {
      // Re-enter from the opposite side (no wrap(): it would stall at the edge).
      if (tx <= ty) o.x = d.x > 0 ? 0 : tile_;
      if (ty <= tx) o.y = d.y > 0 ? 0 : tile_;
    }
    if (t_layer <= t_side) {
      if (t_up <= t_down) {
        if (z_up >= top_) {
          o.z = top_;
          break;  // leaves through the top
        }
        o.z = z_up;
        --k;
      } else {
        if (z_down <= bottom_) {
          o.z = bottom_;
          hit.kind = SphereHit::Kind::Transmit;
          hit.t = travelled;
          hit.position = o;
          return hit;
        }
        o.z = z_down;
        ++k;
      }
    }
  }
  hit.kind = SphereHit::Kind::Escape;
  hit.t = travelled;
  return hit;
}

}  // namespace mcref
