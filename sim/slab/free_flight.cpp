#include "sim/slab/free_flight.h"

#include <algorithm>
#include <cmath>

#include "sim/slab/density_grid.h"
#include "sim/slab/voxel_density.h"

namespace mcref::volume {

namespace {

// Puts the photon on the face of its layer it reached (the bottom if it goes
// deeper) and into the next layer; false if that leaves the stack (`exit` says how).
bool cross_face(const std::vector<MediumLayer>& layers, Photon& p, Flight& exit) {
  if (p.d.z < 0) {
    p.depth = layers[p.layer].bottom;
    if (++p.layer < static_cast<int>(layers.size())) return true;
    p.layer = static_cast<int>(layers.size()) - 1;
    exit = Flight::kExitBottom;
  } else {
    p.depth = layers[p.layer].top;
    if (--p.layer >= 0) return true;
    p.layer = 0;
    exit = Flight::kExitTop;
  }
  return false;
}

// Exact exponential flights through homogeneous layers, sigma_t = rho sigma(w),
// the optical depth carried across layer faces.
Flight track(const std::vector<MediumLayer>& layers, Photon& p, Rng& rng) {
  const double rate = -p.d.z;  // d(depth)/ds
  double tau = -std::log1p(-rng.uniform());
  for (Flight exit;;) {
    const MediumLayer& l = layers[p.layer];
    const double mu_t = l.density * l.phase->sigma(p.d);
    const double dist = rate > 0 ? (l.bottom - p.depth) / rate : rate < 0 ? (l.top - p.depth) / rate : INFINITY;
    const double optical = mu_t > 0 ? mu_t * dist : 0.0;
    if (tau < optical) {
      p.advance(tau / mu_t);
      return Flight::kCollision;
    }
    if (!std::isfinite(dist)) return Flight::kLost;  // horizontal in an empty layer (measure zero)
    tau -= optical;
    p.advance(dist);
    if (!cross_face(layers, p, exit)) return exit;
  }
}

class HomogeneousFlight final : public FreeFlight {
 public:
  explicit HomogeneousFlight(const SlabMedium& m) : m_(m) {}
  Flight fly(Photon& p, Rng& rng) override {
    return track(m_.layers(), p, rng);
  }

 private:
  const SlabMedium& m_;
};

// Delta tracking against the per-cell majorants hi(cell) factor(w)
// (sim/slab/majorant_grid.h), walking the cells along the ray with a 3-D DDA
// (Amanatides & Woo 1987): lateral cells wrap around the tile, depth cells end
// at the layer's faces, where the loop moves to the next layer as track() does.
class GridFlight final : public FreeFlight {
 public:
  explicit GridFlight(const SlabMedium& m) : m_(m), voxels_(*m.voxels()), lookup_(*m.grids()) {}
  Flight fly(Photon& p, Rng& rng) override {
    have_s_ = false;
    const std::vector<MediumLayer>& layers = m_.layers();
    const double rate = -p.d.z, inv_rate = 1 / rate;
    // Once per flight (the direction is fixed): the inverse direction cosines.
    const double inv_dx = 1 / p.d.x, inv_dy = 1 / p.d.y;
    const int sx = p.d.x > 0 ? 1 : -1, sy = p.d.y > 0 ? 1 : -1;
    double tau = -std::log1p(-rng.uniform());
    for (;;) {
      const LayerMajorants& M = m_.majorants()[p.layer];
      const double f = M.factor(p.d);
      const int m = M.lateral;
      // The cell holding the photon (on a face: the cell below it).
      int iz = static_cast<int>(std::upper_bound(M.faces.begin() + 1, M.faces.end() - 1, p.depth) - (M.faces.begin() + 1));
      int ix = 0, iy = 0;
      double tx = INFINITY, ty = INFINITY, dtx = 0, dty = 0;
      if (m > 1) {  // lateral position in cell units, wrapped into the tile
        const double c = M.cell_size, inv_m = 1.0 / m;
        const double xc = wrap_periodic(p.x * M.inv_cell_size, m, inv_m), yc = wrap_periodic(p.y * M.inv_cell_size, m, inv_m);
        ix = static_cast<int>(xc);
        iy = static_cast<int>(yc);
        if (p.d.x != 0) {
          dtx = c * std::fabs(inv_dx);
          tx = ((ix + (sx > 0)) - xc) * c * inv_dx;
        }
        if (p.d.y != 0) {
          dty = c * std::fabs(inv_dy);
          ty = ((iy + (sy > 0)) - yc) * c * inv_dy;
        }
      }
      const auto face_t = [&](int cell) {
        return rate > 0 ? (M.faces[cell + 1] - p.depth) * inv_rate : rate < 0 ? (M.faces[cell] - p.depth) * inv_rate : INFINITY;
      };
      // Horizontal (measure zero) in a row of empty cells: no collision ever.
      if (rate == 0 && !(M.row_hi[iz] > 0)) return Flight::kLost;
      double tz = face_t(iz), t = 0;
      for (long lateral_steps = 0;;) {
        const std::size_t cell = (static_cast<std::size_t>(iz) * m + iy) * m + ix;
        const double mu = M.hi[cell] * f, t_exit = std::min({tx, ty, tz});
        if (tau < mu * (t_exit - t)) {
          t += tau / mu;
          if (accept(M, cell, p, t, rng)) {
            p.advance(t);
            return Flight::kCollision;
          }
          tau = -std::log1p(-rng.uniform());  // null collision: memoryless restart
          continue;
        }
        if (!std::isfinite(t_exit)) return Flight::kLost;  // horizontal in an empty layer (measure zero)
        tau -= mu * (t_exit - t);
        t = t_exit;
        if (t_exit == tz) {
          iz += rate > 0 ? 1 : -1;
          if (iz < 0 || iz == M.depth_cells()) break;
          tz = face_t(iz);
        } else {  // the next lateral cell, without branches on the (random) axis
          if (rate == 0 && ++lateral_steps > (1L << 24)) return Flight::kLost;  // horizontal along empty cells
          const bool step_x = tx <= ty;
          const int nx = ix + sx, ny = iy + sy;
          ix = step_x ? (nx == m ? 0 : nx < 0 ? m - 1 : nx) : ix;
          iy = step_x ? iy : (ny == m ? 0 : ny < 0 ? m - 1 : ny);
          tx += step_x ? dtx : 0.0;
          ty += step_x ? 0.0 : dty;
        }
      }
      p.advance(t);  // through a face of the layer
      if (Flight exit; !cross_face(layers, p, exit)) return exit;
    }
  }
  ScatterSample scatter(const MediumLayer& layer, int k, Vec3 wi, Rng& rng) override {
    const LayerMajorants& M = m_.majorants()[k];
    if (!have_s_ && !M.one_s) return layer.phase->sample(wi, rng);
    const SlabLayer& l = m_.geometry().layers[k];
    return sample_sggx_flakes(have_s_ ? s_ : M.s, l.albedo, l.f0, wi, rng);
  }
  double lateral_period() const override { return m_.geometry().grid.tile; }

 private:
  // Whether the tentative collision at p + t d (in `cell` of the photon's layer)
  // is real: with probability sigma_t(x, w) / (hi(cell) factor(w)).
  bool accept(const LayerMajorants& M, std::size_t cell, const Photon& p, double t, Rng& rng) {
    const double u = rng.uniform() * M.hi[cell];
    if (u < M.lo[cell]) return true;  // below the cell's least density: no lookup needed
    const double x = p.x + p.d.x * t, y = p.y + p.d.y * t, depth = p.depth - p.d.z * t;
    if (!M.s_varies) return u < voxels_.density(p.layer, x, y, depth);
    sggx::Mat3 S;
    const double rho = lookup_.density_and_sggx(p.layer, x, y, depth, S);
    if (!(u < rho * std::sqrt(std::fmax(0.0, sggx::quadratic_form(S, p.d))))) return false;
    s_ = sggx::from_matrix(S);  // the event's S: Cholesky factor and inverse for the sampler
    have_s_ = true;
    return true;
  }

  const SlabMedium& m_;
  const VoxelDensity& voxels_;
  GridLookup lookup_;  // S(x), where it varies
  sggx::Sggx s_;
  bool have_s_ = false;
};

}  // namespace

std::unique_ptr<FreeFlight> make_homogeneous_flight(const SlabMedium& m) { return std::make_unique<HomogeneousFlight>(m); }

std::unique_ptr<FreeFlight> make_flight(const SlabMedium& m) {
  if (m.grids()) return std::make_unique<GridFlight>(m);
  return make_homogeneous_flight(m);
}

}  // namespace mcref::volume
