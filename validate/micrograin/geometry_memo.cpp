#include "validate/micrograin/geometry_memo.h"

#include <array>
#include <cstring>
#include <functional>
#include <mutex>
#include <unordered_map>

namespace mcref {

namespace {

using Key = std::array<double, 11>;

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::uint64_t h = 1469598103934665603ULL;  // FNV-1a over the bits
    for (double v : k) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      h = (h ^ bits) * 1099511628211ULL;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// Sharded, so that parallel checks rarely wait on one another's lock.
struct Shard {
  std::mutex mutex;
  std::unordered_map<Key, double, KeyHash> values;
};
constexpr std::size_t kShards = 64;

}  // namespace

double memo_diffuse_geometry(const micrograin::GrainField& f, Vec3 i, Vec3 o, double ior, micrograin::TwoWay masking) {
  static std::array<Shard, kShards> shards;
  const Key key{f.tau0, f.beta_x, f.beta_y, i.x, i.y, i.z, o.x, o.y, o.z, ior,
                masking == micrograin::TwoWay::Union ? 1.0 : 0.0};
  Shard& s = shards[KeyHash{}(key) % kShards];
  {
    const std::lock_guard<std::mutex> lock(s.mutex);
    const auto it = s.values.find(key);
    if (it != s.values.end()) return it->second;
  }
  // Not under the lock: another thread may compute the same value meanwhile (the same bits).
  const double v = micrograin::gdist_diffuse_geometry(f, i, o, ior, masking);
  const std::lock_guard<std::mutex> lock(s.mutex);
  s.values.emplace(key, v);
  return v;
}

}  // namespace mcref
