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

// Delta tracking against per-cell majorants (sim/slab/majorant_grid.h), layer by
// layer along the ray, the optical depth carried across the layers' faces as
// track() does:
//  - a laterally uniform layer: hi(cell) factor(w) in its depth cells, walked
//    with a DDA in depth (Amanatides & Woo 1987);
//  - a laterally varying layer: ahead_hi(cell) factor(w), the majorant of the box
//    of (rx + 1)(ry + 1) lateral cells from the photon's cell rx cells ahead along
//    x and ry along y (in its depth cell; rx = ry = r, or narrower across the
//    direction's major axis), until a tentative collision or the box's far faces,
//    where the photon's cell starts the next box (the rest of the optical depth
//    carried: the Poisson process of tentative collisions is memoryless).
//    No DDA: most flights end in their first box.
class GridFlight final : public FreeFlight {
  enum class Leg { kCollision, kFace, kLost };

 public:
  explicit GridFlight(const SlabMedium& m) : m_(m), voxels_(*m.voxels()), lookup_(*m.grids()) {}
  Flight fly(Photon& p, Rng& rng) override {
    have_s_ = false;
    double tau = -std::log1p(-rng.uniform());
    for (;;) {
      const LayerMajorants& M = m_.majorants()[p.layer];
      const std::optional<DepthProfile>& profile = m_.depth_profiles()[p.layer];
      const Leg leg = profile                ? fly_profile(*profile, M, p, tau)
                      : M.lateral > 1        ? fly_boxes(M, p, tau, rng)
                                             : fly_depth(M, p, tau, rng);
      if (leg == Leg::kCollision) return Flight::kCollision;
      if (leg == Leg::kLost) return Flight::kLost;
      if (Flight exit; !cross_face(m_.layers(), p, exit)) return exit;
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
  // The depth cell holding a depth (on a face: the cell below it).
  static int depth_cell(const LayerMajorants& M, double depth) {
    return static_cast<int>(std::upper_bound(M.faces.begin() + 1, M.faces.end() - 1, depth) - (M.faces.begin() + 1));
  }

  // A layer varying in depth only, with one S: exact, by inverting the optical
  // depth sigma(w) / |w_z| times the column of rho (sim/slab/depth_profile.h);
  // tau is the optical depth left (carried to the next layer if the photon
  // reaches a face).
  static Leg fly_profile(const DepthProfile& P, const LayerMajorants& M, Photon& p, double& tau) {
    const double rate = -p.d.z, f = M.factor(p.d);
    if (rate == 0) {  // horizontal (measure zero): rho is constant along the ray
      const double mu = P.density(p.depth) * f;
      if (!(mu > 0)) return Leg::kLost;
      p.advance(tau / mu);
      return Leg::kCollision;
    }
    // The column of rho per unit of optical depth, and per unit of depth the distance
    // (divisions apart from tau's chain).
    const double column_per_tau = std::fabs(rate) / f, inv_rate = 1 / rate;
    double amount = f > 0 ? tau * column_per_tau : INFINITY;
    const double depth = P.travel(p.depth, rate > 0, amount);
    p.advance((depth - p.depth) * inv_rate);
    if (amount == 0) {
      p.depth = depth;
      return Leg::kCollision;
    }
    if (f > 0) tau = amount / column_per_tau;  // what is left, past the face
    return Leg::kFace;
  }

  // A laterally uniform layer: the depth cells along the ray; tau is the
  // optical depth left (carried to the next layer if the photon reaches a face).
  Leg fly_depth(const LayerMajorants& M, Photon& p, double& tau, Rng& rng) {
    const double rate = -p.d.z, inv_rate = 1 / rate, f = M.factor(p.d);
    int iz = depth_cell(M, p.depth);
    const auto face_t = [&](int cell) {
      return rate > 0 ? (M.faces[cell + 1] - p.depth) * inv_rate : rate < 0 ? (M.faces[cell] - p.depth) * inv_rate : INFINITY;
    };
    // Horizontal (measure zero) in a row of empty cells: no collision ever.
    if (rate == 0 && !(M.row_hi[iz] > 0)) return Leg::kLost;
    double tz = face_t(iz), t = 0;
    for (;;) {
      const double mu = M.hi[iz] * f;
      if (tau < mu * (tz - t)) {
        t += tau / mu;
        if (accept(M, M.hi[iz], iz, p.layer, p.x + p.d.x * t, p.y + p.d.y * t, p.depth - p.d.z * t, p.d, rng)) {
          p.advance(t);
          return Leg::kCollision;
        }
        tau = -std::log1p(-rng.uniform());  // null collision: memoryless restart
        continue;
      }
      if (!std::isfinite(tz)) return Leg::kLost;  // horizontal in an empty layer (measure zero)
      tau -= mu * (tz - t);
      t = tz;
      iz += rate > 0 ? 1 : -1;
      if (iz < 0 || iz == M.depth_cells()) break;
      tz = face_t(iz);
    }
    p.advance(t);  // through a face of the layer
    return Leg::kFace;
  }

  // A laterally varying layer: boxes of cells ahead of the photon (above). The
  // photon's lateral position is kept as its cell (ix, iy) in the tile and its
  // offset (fx, fy) in [0, 1] in that cell, in cell units; p.x, p.y are written
  // back in the tile, [0, tile]. The box's far faces are rx + 1 (going +) or -rx
  // (going -) from the cell's low face along x, the same with ry along y; per axis,
  // the distance to it is (far - offset) / velocity, +inf when the velocity is +-0
  // (rx, ry >= 1).
  [[gnu::always_inline]] Leg fly_boxes(const LayerMajorants& M, Photon& p, double& tau, Rng& rng) {
    const int m = M.lateral, r = M.reach;
    const double rate = -p.d.z, f = M.factor(p.d), dx = p.d.x * M.inv_cell_size, dy = p.d.y * M.inv_cell_size;
    // The box's shape: narrow across the major axis when the path over r + 1 cells
    // along it moves by at most the narrow reach across it (from anywhere in the cell).
    const double ax = std::fabs(dx), ay = std::fabs(dy), major = std::max(ax, ay), across = std::min(ax, ay) * (r + 1);
    const int narrow = (across <= M.narrow_reach[1] * major) + (across <= M.narrow_reach[0] * major);  // 0: square
    const int shape = narrow + 2 * ((ay > ax) & (narrow != 0));
    const int rx = M.box_reach[shape][0], ry = M.box_reach[shape][1];
    const unsigned char* ahead = M.ahead_hi.data() + (4 * shape + (p.d.x < 0) + 2 * (p.d.y < 0)) * M.hi.size();
    const double inv_dx = 1 / dx, inv_dy = 1 / dy, inv_rate = 1 / rate;
    const bool back_x = std::signbit(dx), back_y = std::signbit(dy), up = rate < 0;
    const double far_x = back_x ? -rx : rx + 1, far_y = back_y ? -ry : ry + 1;
    // Past a far face: the next box starts in the cell beyond it, on its near face.
    const int step_x = back_x ? -rx - 1 : rx + 1, step_y = back_y ? -ry - 1 : ry + 1;
    const double enter_x = back_x ? 1.0 : 0.0, enter_y = back_y ? 1.0 : 0.0;
    double fx = p.x * M.inv_cell_size, fy = p.y * M.inv_cell_size;
    if (!(fx >= 0 && fx < m)) fx = wrap_periodic(fx, m, 1.0 / m);
    if (!(fy >= 0 && fy < m)) fy = wrap_periodic(fy, m, 1.0 / m);
    int ix = std::min(static_cast<int>(fx), m - 1), iy = std::min(static_cast<int>(fy), m - 1);
    fx -= ix;
    fy -= iy;
    int iz = M.depth_cells() == 1 ? 0 : depth_cell(M, p.depth);
    if (rate == 0 && !(M.row_hi[iz] > 0)) return Leg::kLost;  // horizontal in empty cells (measure zero)
    const auto wrap_cell = [m](int i) { return i >= m ? i - m : i < 0 ? i + m : i; };
    // Moves the photon by s (within its box) and makes its cell the next box's start.
    const auto move = [&](double s) {
      const int floor_shift = r + 2;  // offsets stay above -(r + 2): an integer cast floors them
      const double x1 = fx + dx * s, y1 = fy + dy * s;
      const int kx = static_cast<int>(x1 + floor_shift) - floor_shift, ky = static_cast<int>(y1 + floor_shift) - floor_shift;
      fx = x1 - kx;
      fy = y1 - ky;
      ix = wrap_cell(ix + kx);
      iy = wrap_cell(iy + ky);
      p.depth += rate * s;
    };
    Leg leg = Leg::kCollision;
    for (long exits = 0;;) {
      const std::size_t box = (static_cast<std::size_t>(iz) * m + iy) * m + ix;
      const double hi = M.ahead_levels[ahead[box]], mu = hi * f;
      const double face = M.faces[iz + !up];
      const double ex = (far_x - fx) * inv_dx, ey = (far_y - fy) * inv_dy, ez = rate != 0 ? (face - p.depth) * inv_rate : INFINITY;
      const double e = std::min(std::min(ex, ey), ez);  // (std::fmin is a libm call)
      if (tau < mu * e) {  // a tentative collision in the box
        move(tau / mu);
        const std::size_t cell = (static_cast<std::size_t>(iz) * m + iy) * m + ix;
        if (accept(M, hi, cell, p.layer, (ix + fx) * M.cell_size, (iy + fy) * M.cell_size, p.depth, p.d, rng)) break;
        tau = -std::log1p(-rng.uniform());  // null collision: memoryless restart
        continue;
      }
      if (!std::isfinite(e) || (rate == 0 && ++exits > (1L << 24))) {  // horizontal along empty cells (measure zero)
        leg = Leg::kLost;
        break;
      }
      tau -= mu * e;
      const int ix0 = ix, iy0 = iy;
      move(e);
      if (e == ez) {  // exactly on the depth face; into the next depth cell or out of the layer
        p.depth = face;
        iz += up ? -1 : 1;
        if (iz < 0 || iz == M.depth_cells()) {
          leg = Leg::kFace;
          break;
        }
        continue;
      }
      // Exactly on the box's lateral face, in the cell beyond it (progress whatever the rounding).
      const bool hit_x = e == ex, hit_y = e == ey;
      ix = hit_x ? wrap_cell(ix0 + step_x) : ix;
      fx = hit_x ? enter_x : fx;
      iy = hit_y ? wrap_cell(iy0 + step_y) : iy;
      fy = hit_y ? enter_y : fy;
    }
    p.x = (ix + fx) * M.cell_size;
    p.y = (iy + fy) * M.cell_size;
    return leg;
  }

  // Whether a tentative collision at (x, y, depth) of `layer`, in `cell`, drawn
  // against the majorant hi factor(w) (the cell's or its box's), is real: with
  // probability sigma_t(x, w) / (hi factor(w)).
  bool accept(const LayerMajorants& M, double hi, std::size_t cell, int layer, double x, double y, double depth, Vec3 d, Rng& rng) {
    const double u = rng.uniform() * hi;
    if (u < M.lo[cell]) return true;    // below the cell's least density: no lookup needed
    if (u >= M.hi[cell]) return false;  // above its majorant (hi > the cell's: a box's)
    return accept_looked_up(M.s_varies, u, layer, x, y, depth, d);
  }
  // The rest of accept(), out of line: u < sigma_t(x, w) / factor(w), read from the voxels.
  [[gnu::noinline]] bool accept_looked_up(bool s_varies, double u, int layer, double x, double y, double depth, Vec3 d) {
    if (!s_varies) return u < voxels_.density(layer, x, y, depth);
    sggx::Mat3 S;
    const double rho = lookup_.density_and_sggx(layer, x, y, depth, S);
    if (!(u < rho * std::sqrt(std::fmax(0.0, sggx::quadratic_form(S, d))))) return false;
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
