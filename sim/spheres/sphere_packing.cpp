#include "sim/spheres/sphere_packing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "models/core/rng.h"
#include "models/lambert_sphere/decay_rate.h"

namespace mcref {

namespace {
constexpr double kSphereVolume = 4.0 * kPi / 3.0;  // r = 1
constexpr double kOneMinusG = 13.0 / 9.0;          // 1 - g, g = -4/9 (d'Eon Sec. 2)

// Moves the set so that its highest centre sits at z = 0.
void shift_top_to_zero(std::vector<Vec3>& c) {
  if (c.empty()) return;
  double top = c[0].z;
  for (const Vec3& p : c) top = std::max(top, p.z);
  for (Vec3& p : c) p.z -= top;
}
}  // namespace

const char* placement_name(SpherePlacement p) {
  switch (p) {
    case SpherePlacement::poisson: return "poisson";
    case SpherePlacement::rsa: return "rsa";
    default: return "volumetric";
  }
}

double SpherePacking::number_density() const {
  // Independent centres: the union covers f = 1 - exp(-n V); otherwise f = n V.
  if (placement == SpherePlacement::rsa) return volume_fraction / kSphereVolume;
  return -std::log1p(-volume_fraction) / kSphereVolume;
}

double SpherePacking::depth_in_mfp() const {
  return depth_mfp > 0 ? depth_mfp : transmission_depth_mfp(albedo.max(), transmission_threshold);
}

double SpherePacking::expected_count() const {
  return placement == SpherePlacement::volumetric ? 0.0 : number_density() * tile * tile * depth();
}

double transmission_depth_mfp(double c, double threshold) {
  if (c >= 1.0) return 4.0 / (3.0 * kOneMinusG * threshold);  // conservative: T ~ 4 / (3 (1-g) D)
  return std::log(kTransmissionPrefactor / threshold) / lambert_sphere::decay_rate(c);
}

std::vector<Vec3> place_poisson(const SpherePacking& p, Rng& rng) {
  const double depth = p.depth();
  const std::uint64_t n = rng.poisson(p.number_density() * p.tile * p.tile * depth);
  std::vector<Vec3> c(n);
  for (Vec3& x : c) x = {rng.uniform() * p.tile, rng.uniform() * p.tile, -rng.uniform() * depth};
  shift_top_to_zero(c);
  return c;
}

std::vector<Vec3> place_rsa(const SpherePacking& p, Rng& rng) {
  // RSA over-fills a free boundary (a centre near it has half its exclusion
  // neighbourhood empty): twice the bulk density within half a radius of the
  // face. So the packing is periodic in z too, over kRsaPadding more than the
  // depth on both sides, and cut to [-depth, 0]: a bulk packing cut by planes.
  const double depth = p.depth(), side = p.tile, made = depth + 2 * kRsaPadding;
  const std::size_t target = static_cast<std::size_t>(std::llround(p.volume_fraction * side * side * made / kSphereVolume));
  // Grid of cells at least one diameter wide: a new sphere can only overlap
  // spheres whose centres lie in the 27 cells around its own.
  const int nx = std::max(1, static_cast<int>(side / 2.0));
  const int nz = std::max(1, static_cast<int>(made / 2.0));
  const double cx = side / nx, cz = made / nz;
  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(nx) * nx * nz);
  auto cell_index = [&](int ix, int iy, int iz) { return (static_cast<std::size_t>(iz) * nx + iy) * nx + ix; };
  std::vector<Vec3> c;
  c.reserve(target);
  const std::uint64_t budget = 2000ull * target + 1000000ull;
  std::uint64_t attempts = 0;
  while (c.size() < target) {
    if (++attempts > budget)
      throw std::runtime_error("RSA placement stalled at volume fraction " +
                               std::to_string(c.size() * kSphereVolume / (side * side * made)) + " of " +
                               std::to_string(p.volume_fraction) + " (near jamming); lower volume_fraction");
    const Vec3 x{rng.uniform() * side, rng.uniform() * side, kRsaPadding - rng.uniform() * made};
    const int ix = std::min(nx - 1, static_cast<int>(x.x / cx));
    const int iy = std::min(nx - 1, static_cast<int>(x.y / cx));
    const int iz = std::min(nz - 1, static_cast<int>((kRsaPadding - x.z) / cz));
    bool free = true;
    for (int dz = -1; dz <= 1 && free; ++dz) {
      const int jz = (iz + dz + nz) % nz;
      for (int dy = -1; dy <= 1 && free; ++dy)
        for (int dx = -1; dx <= 1 && free; ++dx) {
          const int jx = (ix + dx + nx) % nx, jy = (iy + dy + nx) % nx;
          for (std::uint32_t k : cells[cell_index(jx, jy, jz)]) {
            double ddx = x.x - c[k].x, ddy = x.y - c[k].y;
            ddx -= side * std::round(ddx / side);
            ddy -= side * std::round(ddy / side);
            const double ddz = x.z - c[k].z - made * std::round((x.z - c[k].z) / made);
            if (ddx * ddx + ddy * ddy + ddz * ddz < 4.0) {
              free = false;
              break;
            }
          }
        }
    }
    if (!free) continue;
    cells[cell_index(ix, iy, iz)].push_back(static_cast<std::uint32_t>(c.size()));
    c.push_back(x);
  }
  c.erase(std::remove_if(c.begin(), c.end(), [&](const Vec3& x) { return x.z > 0 || x.z < -depth; }), c.end());
  shift_top_to_zero(c);
  return c;
}

std::vector<Vec3> place_spheres(const SpherePacking& p, Rng& rng) {
  switch (p.placement) {
    case SpherePlacement::poisson: return place_poisson(p, rng);
    case SpherePlacement::rsa: return place_rsa(p, rng);
    default: throw std::logic_error("place_spheres: the volumetric placement has no spheres");
  }
}

}  // namespace mcref
