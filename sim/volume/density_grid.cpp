#include "sim/volume/density_grid.h"

#include <cmath>
#include <mutex>

#include <openvdb/io/File.h>

namespace mcref::volume {

namespace {
void init_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

const char* phase_name(SlabPhase p) {
  switch (p) {
    case SlabPhase::kSggxSurface: return "sggx_surface";
    case SlabPhase::kSggxFiber: return "sggx_fiber";
    case SlabPhase::kHenyeyGreenstein: return "hg";
    case SlabPhase::kIsotropic: return "isotropic";
    case SlabPhase::kLambertSphere: break;
  }
  return "lambert_sphere";
}
}  // namespace

DensityGrids::DensityGrids(const SlabGeometry& g) : geometry_(g) {
  init_openvdb();
  const int n = g.grid.lateral_voxels, nz = g.grid.depth_voxels;
  n_lateral_ = n;
  hx_ = g.grid.tile / n;
  double top = 0;
  for (std::size_t k = 0; k < g.layers.size(); ++k) {
    const SlabLayer& l = g.layers[k];
    const double hz = l.thickness / nz, bottom = top + l.thickness;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("layer" + std::to_string(k) + "_density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform();
    xf->preScale(openvdb::Vec3d(hx_, hx_, hz));
    xf->postTranslate(openvdb::Vec3d(0, 0, -bottom));
    grid->setTransform(xf);
    auto acc = grid->getAccessor();
    double vmax = 0;
    for (int kz = 0; kz <= nz; ++kz) {
      const double s = 1.0 - static_cast<double>(kz) / nz;  // relative depth from the layer's top
      const float v = static_cast<float>(l.density * l.profile.at(s));
      vmax = std::fmax(vmax, v);
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) acc.setValue(openvdb::Coord(i, j, kz), v);
    }
    grid->insertMeta("phase", openvdb::StringMetadata(phase_name(l.phase)));
    grid->insertMeta("thickness", openvdb::DoubleMetadata(l.thickness));
    grid->insertMeta("alpha", openvdb::DoubleMetadata(l.alpha));
    grid->insertMeta("orientation", openvdb::Vec3DMetadata(openvdb::Vec3d(l.orientation.x, l.orientation.y, l.orientation.z)));
    grid->insertMeta("hg_g", openvdb::DoubleMetadata(l.g));
    grid->insertMeta("albedo", openvdb::Vec3DMetadata(openvdb::Vec3d(l.albedo.r, l.albedo.g, l.albedo.b)));
    grid->insertMeta("f0", openvdb::Vec3DMetadata(openvdb::Vec3d(l.f0.r, l.f0.g, l.f0.b)));
    grid->insertMeta("lateral_period", openvdb::DoubleMetadata(g.grid.tile));
    grids_.push_back(grid);
    max_.push_back(vmax);
    top_.push_back(top);
    bottom_.push_back(bottom);
    hz_.push_back(hz);
    top = bottom;
  }
}

double DensityGrids::column_optical_thickness(std::size_t k) const {
  auto acc = grids_[k]->getConstAccessor();
  const int nz = geometry_.grid.depth_voxels;
  double sum = 0;
  for (int kz = 0; kz < nz; ++kz)
    sum += 0.5 * (acc.getValue(openvdb::Coord(0, 0, kz)) + acc.getValue(openvdb::Coord(0, 0, kz + 1)));
  return sum * hz_[k];
}

GridLookup::GridLookup(const DensityGrids& g) : g_(g) {
  for (const auto& grid : g.grids_) acc_.push_back(grid->getConstAccessor());
}

double GridLookup::density(int k, double x, double y, double depth) {
  const double n = g_.n_lateral_;
  double ix = std::fmod(x / g_.hx_, n), iy = std::fmod(y / g_.hx_, n);
  if (ix < 0) ix += n;
  if (iy < 0) iy += n;
  const double iz = std::fmin(g_.geometry_.grid.depth_voxels, std::fmax(0.0, (g_.bottom_[k] - depth) / g_.hz_[k]));
  return openvdb::tools::BoxSampler::sample(acc_[k], openvdb::Vec3R(ix, iy, iz));
}

void write_vdb(const std::string& path, const DensityGrids& g) {
  init_openvdb();
  openvdb::GridPtrVec out(g.grids().begin(), g.grids().end());
  openvdb::io::File file(path);
  file.write(out);
  file.close();
}

}  // namespace mcref::volume
