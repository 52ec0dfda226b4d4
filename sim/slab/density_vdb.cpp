#include "sim/slab/density_vdb.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <map>
#include <sstream>

#include "models/sggx/sggx_distribution.h"
#include "sim/experiment/config_error.h"
#include "sim/files/input_file.h"
#include "sim/hdf5/file_seal.h"

namespace mcref::volume {

namespace {

std::string coord_text(const openvdb::Coord& c) {
  return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + ")";
}

std::string number_text(double v, int digits = 9) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

// The grid's index-to-world map must be the experiment's: scale (hx, hx, hz),
// axis-aligned, voxel (0, 0, 0) at (0, 0, -bottom); to 1e-6 relative in the
// scale, and in the origin to 1e-4 of a voxel plus the float32 rounding of the
// layer's depth (1e-7 of it; a map stored in float32 passes), at most 1e-2 of a
// voxel; each entry also to 1e-15 of the depth (OpenVDB's maps, even export-vdb's
// own, round the voxel size in double at the layer's depth: 5e-17 of it was
// seen). Read from the map's matrix (world = index M, translation in its last row).
void check_transform(const std::string& file, const openvdb::GridBase& grid, double hx, double hz, double bottom,
                     const SlabGrid& g, double thickness) {
  const openvdb::math::MapBase::ConstPtr map = grid.transform().baseMap();
  const openvdb::Mat4d m = map->isLinear() ? map->getAffineMap()->getMat4() : openvdb::Mat4d::zero();
  const double want[3] = {hx, hx, hz}, origin[3] = {0, 0, -bottom};
  const double depth_slack = 1e-15 * (bottom + g.tile);
  bool ok = map->isLinear();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      ok = ok && std::fabs(m(r, c) - (r == c ? want[c] : 0.0)) <= 1e-6 * (r == c ? want[c] : std::min(hx, hz)) + depth_slack;
    const double float32 = std::min(1e-4 * want[r] + 1e-7 * std::fabs(origin[r]), 1e-2 * want[r]);
    ok = ok && std::fabs(m(3, r) - origin[r]) <= float32 + depth_slack;
  }
  if (ok) return;
  const auto t = [](double v) { return number_text(v, 12); };
  std::string has = "its transform is not linear (" + map->type() + ")";
  if (map->isLinear()) {
    const bool rotated = m(0, 1) != 0 || m(0, 2) != 0 || m(1, 0) != 0 || m(1, 2) != 0 || m(2, 0) != 0 || m(2, 1) != 0;
    has = "its voxels are " + t(m(0, 0)) + " x " + t(m(1, 1)) + " x " + t(m(2, 2)) + (rotated ? " (rotated)" : "") +
          " with voxel (0, 0, 0) at (" + t(m(3, 0)) + ", " + t(m(3, 1)) + ", " + t(m(3, 2)) + ")";
  }
  throw ConfigError(file, grid.getName(),
                    has + "; the experiment needs axis-aligned voxels " + t(hx) + " x " + t(hx) + " x " + t(hz) +
                        " (tile " + t(g.tile) + " / lateral_voxels " + std::to_string(g.lateral_voxels) + ", thickness " +
                        t(thickness) + " / depth_voxels " + std::to_string(g.depth_voxels) +
                        ") with voxel (0, 0, 0) at (0, 0, " + t(-bottom) + ")");
}

// export-vdb's metadata, where the file has it, must agree with the experiment
// (a tile exported at another size can otherwise have voxels of the right size).
void check_metadata(const std::string& file, const openvdb::GridBase& grid, const char* name, double expected,
                    const std::string& key) {
  double value = expected, rel = 1e-9;
  if (const auto d = grid.getMetadata<openvdb::DoubleMetadata>(name)) value = d->value();
  if (const auto f = grid.getMetadata<openvdb::FloatMetadata>(name)) value = f->value(), rel = 1e-6;
  if (std::fabs(value - expected) <= rel * std::fabs(expected)) return;
  throw ConfigError(file, grid.getName(),
                    std::string("its metadata ") + name + " is " + number_text(value) + " (as exported); the experiment's " +
                        key + " is " + number_text(expected));
}

// Every active value (voxel or tile) lies in i, j in [0, n), k in [0, nz].
template <typename Grid>
void check_extent(const std::string& file, const Grid& grid, int n, int nz) {
  const openvdb::CoordBBox inside(openvdb::Coord(0, 0, 0), openvdb::Coord(n - 1, n - 1, nz));
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    const openvdb::CoordBBox box = it.getBoundingBox();
    if (!inside.isInside(box))
      throw ConfigError(file, grid.getName(),
                        "active voxel " + coord_text(inside.isInside(box.min()) ? box.max() : box.min()) +
                            " lies outside i, j in [0, " + std::to_string(n) + "), k in [0, " + std::to_string(nz) +
                            "] (lateral_voxels " + std::to_string(n) + ", depth_voxels " + std::to_string(nz) +
                            "): the grid is larger than the experiment's, or it stores the periodic seam i or j = " +
                            std::to_string(n) + " (export-vdb does not)");
  }
}

// S grids, if the file has them, must hold the experiment's S (to their precision).
template <typename Grid>
void check_matrix_grid(const std::string& file, const Grid& grid, const openvdb::Vec3d& expected, int n, int nz) {
  using V = typename Grid::ValueType;
  const V want(static_cast<typename V::value_type>(expected[0]), static_cast<typename V::value_type>(expected[1]),
               static_cast<typename V::value_type>(expected[2]));
  check_extent(file, grid, n, nz);
  auto acc = grid.getConstAccessor();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k <= nz; ++k)
        if (const V v = acc.getValue(openvdb::Coord(i, j, k)); v != want)
          throw ConfigError(file, grid.getName(),
                            "voxel " + coord_text(openvdb::Coord(i, j, k)) + " holds (" + number_text(v[0]) + ", " +
                                number_text(v[1]) + ", " + number_text(v[2]) + "), not the experiment's (" +
                                number_text(want[0]) + ", " + number_text(want[1]) + ", " + number_text(want[2]) +
                                "): S is not read from the file but from the layer's alpha and orientation; "
                                "set those, or remove the S grids");
}

}  // namespace

std::string read_density_vdb(const std::string& path, const std::string& config_file, const std::string& key,
                             SlabGeometry& geometry) {
  const std::string bytes = read_input_file(path, config_file, key);
  openvdb::initialize();
  openvdb::GridPtrVecPtr grids;
  try {
    std::istringstream in(bytes);
    grids = openvdb::io::Stream(in).getGrids();
  } catch (const std::exception& err) {
    throw ConfigError(config_file, key, "'" + path + "' is not a readable OpenVDB file (" + err.what() + ")");
  }
  std::map<std::string, openvdb::GridBase::Ptr> by_name;
  std::string names;
  for (const openvdb::GridBase::Ptr& g : *grids) {
    if (!by_name.emplace(g->getName(), g).second)
      throw ConfigError(path, g->getName(), "two grids have this name; each layer's grids must be unique");
    names += (names.empty() ? "" : ", ") + g->getName();
  }
  const SlabGrid& sg = geometry.grid;
  const int n = sg.lateral_voxels, nz = sg.depth_voxels;
  const double hx = sg.tile / n;
  double top = 0;
  for (std::size_t k = 0; k < geometry.layers.size(); ++k) {
    SlabLayer& l = geometry.layers[k];
    const double hz = l.thickness / nz, bottom = top + l.thickness;
    const std::string base = "layer" + std::to_string(k) + "_";
    const auto found = by_name.find(base + "density");
    if (found == by_name.end())
      throw ConfigError(path, base + "density",
                        "no such grid (the experiment has " + std::to_string(geometry.layers.size()) +
                            " layers, one density grid each; the file holds: " + (names.empty() ? "no grid" : names) + ")");
    const auto rho = openvdb::gridPtrCast<openvdb::FloatGrid>(found->second);
    if (!rho) throw ConfigError(path, found->first, "is a " + found->second->type() + " grid; densities need a FloatGrid");
    check_transform(path, *rho, hx, hz, bottom, sg, l.thickness);
    check_metadata(path, *rho, "lateral_period", sg.tile, "geometry.tile");
    check_metadata(path, *rho, "thickness", l.thickness, "geometry.layer." + std::to_string(k) + ".thickness");
    check_extent(path, *rho, n, nz);
    auto voxels = std::make_shared<std::vector<float>>(static_cast<std::size_t>(n) * n * (nz + 1));
    auto acc = rho->getConstAccessor();
    double column_sum = 0, column_max = 0;
    bool lateral = false;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        float* column = voxels->data() + (static_cast<std::size_t>(i) * n + j) * (nz + 1);
        double column_mean = 0;  // trapezoids between the voxel planes, over the layer
        for (int z = 0; z <= nz; ++z) {
          const float v = acc.getValue(openvdb::Coord(i, j, z));
          if (!(v >= 0 && v <= 1e9))
            throw ConfigError(path, found->first,
                              "voxel " + coord_text(openvdb::Coord(i, j, z)) + " is " + number_text(v) +
                                  "; a density must be finite, in [0, 1e9]");
          column[z] = v;
          lateral = lateral || v != (*voxels)[static_cast<std::size_t>(z)];
          if (z > 0) column_mean += 0.5 * (static_cast<double>(column[z - 1]) + v) / nz;
        }
        column_sum += column_mean;
        column_max = std::max(column_max, column_mean);
      }
    if (!(l.thickness * column_max <= 1e6))
      throw ConfigError(path, found->first,
                        "a column's optical thickness T rho is " + number_text(l.thickness * column_max) +
                            ", more than 1e6; lower the densities or the layer's thickness");
    l.voxels = voxels;
    l.density = column_sum / (static_cast<double>(n) * n);  // the layer's mean
    l.profile = DensityProfile();
    l.varies_laterally = lateral;
    by_name.erase(found);
    for (const char* part : {"S_diag", "S_offdiag"}) {
      const auto s = by_name.find(base + part);
      if (s == by_name.end()) continue;
      if (!l.is_sggx())
        throw ConfigError(path, s->first, "layer " + std::to_string(k) + " is not an SGGX layer: it has no S");
      const sggx::Mat3 S = (l.phase == SlabPhase::kSggxSurface ? sggx::surface_like(l.alpha, l.orientation)
                                                                : sggx::fiber_like(l.alpha, l.orientation)).S;
      const openvdb::Vec3d want = part == std::string("S_diag") ? openvdb::Vec3d(S(0, 0), S(1, 1), S(2, 2))
                                                                : openvdb::Vec3d(S(0, 1), S(0, 2), S(1, 2));
      if (const auto f = openvdb::gridPtrCast<openvdb::Vec3SGrid>(s->second)) {
        check_transform(path, *f, hx, hz, bottom, sg, l.thickness);
        check_matrix_grid(path, *f, want, n, nz);
      } else if (const auto d = openvdb::gridPtrCast<openvdb::Vec3DGrid>(s->second)) {
        check_transform(path, *d, hx, hz, bottom, sg, l.thickness);
        check_matrix_grid(path, *d, want, n, nz);
      } else {
        throw ConfigError(path, s->first, "is a " + s->second->type() + " grid; S grids are Vec3SGrid or Vec3DGrid");
      }
      by_name.erase(s);
    }
    top = bottom;
  }
  if (!by_name.empty())
    throw ConfigError(path, by_name.begin()->first,
                      "is not a grid the experiment reads (layer<k>_density, and layer<k>_S_diag, layer<k>_S_offdiag for "
                      "SGGX layers, k < " + std::to_string(geometry.layers.size()) + ")");
  return content_digest(bytes);
}

}  // namespace mcref::volume
