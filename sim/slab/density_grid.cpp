#include "sim/slab/density_grid.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "models/sggx/sggx_distribution.h"

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

openvdb::Vec3DGrid::Ptr make_matrix_grid(const std::string& name, const openvdb::math::Transform::Ptr& xf,
                                         const char* components) {
  auto grid = openvdb::Vec3DGrid::create(openvdb::Vec3d(0, 0, 0));
  grid->setName(name);
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->setVectorType(openvdb::VEC_INVARIANT);
  grid->setTransform(xf->copy());
  grid->insertMeta("components", openvdb::StringMetadata(components));
  return grid;
}
}  // namespace

double largest_eigenvalue(const sggx::Mat3& a) {
  // Cyclic Jacobi rotations (accurate to rounding also for repeated
  // eigenvalues, where the trigonometric closed form loses half the digits).
  sggx::Mat3 m = a;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = m(0, 1) * m(0, 1) + m(0, 2) * m(0, 2) + m(1, 2) * m(1, 2);
    const double diag = m(0, 0) * m(0, 0) + m(1, 1) * m(1, 1) + m(2, 2) * m(2, 2);
    if (!(off > 1e-32 * diag)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (m(p, q) == 0) continue;
        const double theta = (m(q, q) - m(p, p)) / (2 * m(p, q));
        const double t = (theta >= 0 ? 1 : -1) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // m = J^T m J, columns then rows
          const double mkp = m(k, p), mkq = m(k, q);
          m(k, p) = c * mkp - s * mkq;
          m(k, q) = s * mkp + c * mkq;
        }
        for (int k = 0; k < 3; ++k) {
          const double mpk = m(p, k), mqk = m(q, k);
          m(p, k) = c * mpk - s * mqk;
          m(q, k) = s * mpk + c * mqk;
        }
      }
  }
  return std::max({m(0, 0), m(1, 1), m(2, 2)});
}

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
      const float profile = static_cast<float>(l.density * l.profile.at(s));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          // density_vdb's voxels (column i = N, j = N repeating 0), else rho profile(s).
          const float v = l.voxels ? (*l.voxels)[(static_cast<std::size_t>(i % n) * n + j % n) * (nz + 1) + kz] : profile;
          vmax = std::fmax(vmax, v);
          acc.setValue(openvdb::Coord(i, j, kz), v);
        }
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
    // The SGGX matrix field of the layer (constant alpha and omega_p per layer).
    openvdb::Vec3DGrid::Ptr sd, so;
    double smax = 1;
    if (l.is_sggx()) {
      const std::string base = "layer" + std::to_string(k) + "_S_";
      sd = make_matrix_grid(base + "diag", xf, "S_xx S_yy S_zz");
      so = make_matrix_grid(base + "offdiag", xf, "S_xy S_xz S_yz");
      for (auto& sg : {sd, so}) {
        sg->insertMeta("phase", openvdb::StringMetadata(phase_name(l.phase)));
        sg->insertMeta("alpha", openvdb::DoubleMetadata(l.alpha));
        sg->insertMeta("orientation", openvdb::Vec3DMetadata(openvdb::Vec3d(l.orientation.x, l.orientation.y, l.orientation.z)));
        sg->insertMeta("lateral_period", openvdb::DoubleMetadata(g.grid.tile));
      }
      auto ad = sd->getAccessor();
      auto ao = so->getAccessor();
      smax = 0;
      for (int kz = 0; kz <= nz; ++kz) {
        const sggx::Mat3 S = (l.phase == SlabPhase::kSggxSurface ? sggx::surface_like(l.alpha, l.orientation)
                                                                  : sggx::fiber_like(l.alpha, l.orientation)).S;
        const openvdb::Vec3d dv(S(0, 0), S(1, 1), S(2, 2)), ov(S(0, 1), S(0, 2), S(1, 2));
        // With a relative margin for rounding (Jacobi is accurate to a few ulps).
        smax = std::fmax(smax, std::sqrt(largest_eigenvalue(S)) * (1 + 1e-10));
        for (int i = 0; i <= n; ++i)
          for (int j = 0; j <= n; ++j) {
            ad.setValue(openvdb::Coord(i, j, kz), dv);
            ao.setValue(openvdb::Coord(i, j, kz), ov);
          }
      }
    }
    s_diag_.push_back(sd);
    s_offdiag_.push_back(so);
    max_sigma_.push_back(smax);
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

openvdb::GridPtrVec DensityGrids::all_grids() const {
  openvdb::GridPtrVec out;
  for (std::size_t k = 0; k < grids_.size(); ++k) {
    out.push_back(grids_[k]);
    if (s_diag_[k]) {
      out.push_back(s_diag_[k]);
      out.push_back(s_offdiag_[k]);
    }
  }
  return out;
}

GridLookup::GridLookup(const DensityGrids& g) : g_(g) {
  for (std::size_t k = 0; k < g.grids_.size(); ++k) {
    acc_.push_back(g.grids_[k]->getConstAccessor());
    diag_.push_back(g.s_diag_[k] ? std::make_unique<openvdb::Vec3DGrid::ConstAccessor>(g.s_diag_[k]->getConstAccessor()) : nullptr);
    off_.push_back(g.s_offdiag_[k] ? std::make_unique<openvdb::Vec3DGrid::ConstAccessor>(g.s_offdiag_[k]->getConstAccessor()) : nullptr);
  }
}

openvdb::Vec3R GridLookup::index(int k, double x, double y, double depth) const {
  const double n = g_.n_lateral_;
  double ix = std::fmod(x / g_.hx_, n), iy = std::fmod(y / g_.hx_, n);
  if (ix < 0) ix += n;
  if (iy < 0) iy += n;
  const double iz = std::fmin(g_.geometry_.grid.depth_voxels, std::fmax(0.0, (g_.bottom_[k] - depth) / g_.hz_[k]));
  return {ix, iy, iz};
}

double GridLookup::density(int k, double x, double y, double depth) {
  return openvdb::tools::BoxSampler::sample(acc_[k], index(k, x, y, depth));
}

sggx::Mat3 GridLookup::matrix_at(int k, const openvdb::Vec3R& ijk) {
  const openvdb::Vec3d d = openvdb::tools::BoxSampler::sample(*diag_[k], ijk);
  const openvdb::Vec3d o = openvdb::tools::BoxSampler::sample(*off_[k], ijk);
  sggx::Mat3 s;
  s(0, 0) = d[0];
  s(1, 1) = d[1];
  s(2, 2) = d[2];
  s(0, 1) = s(1, 0) = o[0];
  s(0, 2) = s(2, 0) = o[1];
  s(1, 2) = s(2, 1) = o[2];
  return s;
}

sggx::Mat3 GridLookup::sggx_matrix(int k, double x, double y, double depth) {
  return matrix_at(k, index(k, x, y, depth));
}

double GridLookup::density_and_sggx(int k, double x, double y, double depth, sggx::Mat3& s) {
  const openvdb::Vec3R ijk = index(k, x, y, depth);
  s = matrix_at(k, ijk);
  return openvdb::tools::BoxSampler::sample(acc_[k], ijk);
}

}  // namespace mcref::volume
