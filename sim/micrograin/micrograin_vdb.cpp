#include "sim/micrograin/micrograin_vdb.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>

#include <openvdb/io/File.h>

#include "models/core/rng.h"
#include "sim/files/vdb_file.h"

namespace mcref {

namespace {
void init_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}
}  // namespace

MicrograinVoxels micrograin_voxels(const MicrograinGeometry& g, double voxel_size) {
  const double h = voxel_size > 0 ? voxel_size : g.radius / 8;
  const double side = g.tile * g.radius;
  MicrograinVoxels v;
  const double nx = std::max(1.0, std::round(side / h)), nz = std::max(1.0, std::ceil(g.c() / h - 1e-9));
  // Saturate before the int conversion; the count check reports the size.
  v.nx = static_cast<int>(std::min(nx, 2e9));
  v.nz = static_cast<int>(std::min(nz, 2e9));
  v.hx = side / v.nx;
  v.hz = g.c() / v.nz;
  return v;
}

std::string voxel_count_text(const MicrograinVoxels& v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v.count());  // no integer cast: counts may pass 2^63
  return buf;
}

openvdb::FloatGrid::Ptr micrograin_grid(const MicrograinField& f, const MicrograinVoxels& v, std::uint64_t run_seed,
                                        std::uint64_t realization) {
  if (v.count() > kMaxMicrograinVoxels)
    throw std::invalid_argument("the grain grid would hold " + voxel_count_text(v) +
                                " voxels (more than 2e8); use a larger voxel size or a smaller tile");
  init_openvdb();
  const MicrograinGeometry& g = f.geometry();
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("grains");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform();
  xf->preScale(openvdb::Vec3d(v.hx, v.hx, v.hz));
  xf->postTranslate(openvdb::Vec3d(0.5 * v.hx, 0.5 * v.hx, 0.5 * v.hz));
  grid->setTransform(xf);
  auto acc = grid->getAccessor();
  // Walk the grains, not the voxels: each marks the voxel centres inside its
  // unit-space sphere (periodic images included), so the cost is the occupied volume.
  const double ux = v.hx / g.r_x(), uy = v.hx / g.r_y(), uz = v.hz / g.c();  // voxel size in unit space
  for (std::size_t n = 0; n < f.grain_count(); ++n) {
    const Vec3 c = f.unit_centre(n);
    const int i0 = static_cast<int>(std::floor((c.x - 1) / ux - 0.5)), i1 = static_cast<int>(std::ceil((c.x + 1) / ux - 0.5));
    const int j0 = static_cast<int>(std::floor((c.y - 1) / uy - 0.5)), j1 = static_cast<int>(std::ceil((c.y + 1) / uy - 0.5));
    for (int i = i0; i <= i1; ++i) {
      const double dx = (i + 0.5) * ux - c.x;
      for (int j = j0; j <= j1; ++j) {
        const double dy = (j + 0.5) * uy - c.y;
        const double r2 = dx * dx + dy * dy;
        if (r2 >= 1) continue;
        const int wi = ((i % v.nx) + v.nx) % v.nx, wj = ((j % v.nx) + v.nx) % v.nx;
        for (int k = 0; k < v.nz; ++k) {
          const double z = (k + 0.5) * uz;
          if (r2 + z * z >= 1) break;
          acc.setValue(openvdb::Coord(wi, wj, k), 1.0f);
        }
      }
    }
  }
  grid->insertMeta("tau0", openvdb::DoubleMetadata(g.tau0));
  grid->insertMeta("beta_x", openvdb::DoubleMetadata(g.beta_x));
  grid->insertMeta("beta_y", openvdb::DoubleMetadata(g.beta_y));
  grid->insertMeta("radius", openvdb::DoubleMetadata(g.radius));
  grid->insertMeta("tile", openvdb::DoubleMetadata(g.tile));
  grid->insertMeta("tile_side", openvdb::DoubleMetadata(f.tile_side()));
  grid->insertMeta("c", openvdb::DoubleMetadata(g.c()));
  // run.seed (< 2^63), not the realization's derived seed: that one fills 64 bits and read as Int64 was negative.
  grid->insertMeta("seed", openvdb::Int64Metadata(static_cast<openvdb::Int64>(run_seed)));
  grid->insertMeta("realization", openvdb::Int64Metadata(static_cast<openvdb::Int64>(realization)));
  grid->insertMeta("grain_count", openvdb::Int64Metadata(static_cast<openvdb::Int64>(f.grain_count())));
  return grid;
}

void write_micrograin_vdb(const std::string& path, const openvdb::FloatGrid::Ptr& grid) {
  init_openvdb();
  write_vdb_file(path, openvdb::GridCPtrVec{grid});
}

}  // namespace mcref
