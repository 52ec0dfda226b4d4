#include "sim/slab/majorant_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "sim/slab/density_grid.h"

namespace mcref::volume {

namespace {

// ahead_levels: 0, then top r^(q - 255) for q = 1..255, the ratio r spanning
// top / least (the least positive value to encode) when that keeps it in
// [1.001, 1.05]: rounding up to a level loosens a majorant by less than r.
std::array<double, 256> geometric_levels(double top, double least) {
  std::array<double, 256> levels{};
  const double r = std::clamp(least > 0 ? std::pow(top / least, 1.0 / 254) : 1.05, 1.001, 1.05);
  for (int q = 1; q < 256; ++q) levels[q] = q == 255 ? top : top * std::pow(r, q - 255);
  return levels;
}

// The least level >= v (a majorant stays one), as its index; v <= levels[255].
// A binary search without branches on the data: below = the last level < v.
unsigned char level_above(double v, const std::array<double, 256>& levels) {
  if (!(v > 0)) return 0;
  int below = 0;
  for (int step = 128; step > 0; step /= 2) below = levels[below + step] < v ? below + step : below;
  return static_cast<unsigned char>(below + 1);
}

// Bounds of the field over the corners of a voxel cell.
struct Bounds {
  double lo = INFINITY, hi = 0;  // density
  double sigma = 0;              // max sqrt(lambda_max(S)) (layers whose S varies)
};

// Bounds of a run of voxel cells in depth (one lateral cell): their union, and
// how far apart the cells' own bounds are.
struct Run {
  Bounds all;
  double least_hi = INFINITY, greatest_lo = 0, least_sigma = INFINITY;
  void add(const Bounds& b) {
    all.lo = std::min(all.lo, b.lo);
    all.hi = std::max(all.hi, b.hi);
    all.sigma = std::max(all.sigma, b.sigma);
    least_hi = std::min(least_hi, b.hi);
    greatest_lo = std::max(greatest_lo, b.lo);
    least_sigma = std::min(least_sigma, b.sigma);
  }
  // Merged, the cells' majorants and minorants move by at most kMergeRange.
  bool narrow() const {
    return least_hi >= (1 - kMergeRange) * all.hi && all.lo >= (1 - kMergeRange) * greatest_lo &&
           least_sigma >= (1 - kMergeRange) * all.sigma;
  }
};

template <class Grid>
bool all_active_equal(const Grid& grid, const typename Grid::ValueType& v) {
  for (auto it = grid.cbeginValueOn(); it; ++it)
    if (*it != v) return false;
  return true;
}

// A layer's voxels: the density from a dense copy (i, j in [0, N], z in [0,
// depth_voxels], read once through OpenVDB: cell_bounds reads each many times),
// S through OpenVDB.
class LayerReader {
 public:
  LayerReader(const DensityGrids& g, std::size_t k)
      : planes_(g.geometry().grid.lateral_voxels + 1), depth_planes_(g.geometry().grid.depth_voxels + 1) {
    rho_.resize(static_cast<std::size_t>(planes_) * planes_ * depth_planes_);
    auto acc = g.grids()[k]->getConstAccessor();
    for (int i = 0; i < planes_; ++i)
      for (int j = 0; j < planes_; ++j)
        for (int z = 0; z < depth_planes_; ++z) rho_[index(i, j, z)] = acc.getValue(openvdb::Coord(i, j, z));
    if (g.has_sggx(k)) {
      diag_ = std::make_unique<openvdb::Vec3DGrid::ConstAccessor>(g.s_diag(k)->getConstAccessor());
      off_ = std::make_unique<openvdb::Vec3DGrid::ConstAccessor>(g.s_offdiag(k)->getConstAccessor());
    }
  }
  double density(int i, int j, int z) const { return rho_[index(i, j, z)]; }
  sggx::Mat3 matrix(int i, int j, int z) {
    const openvdb::Coord c(i, j, z);
    const openvdb::Vec3d d = diag_->getValue(c), o = off_->getValue(c);
    sggx::Mat3 s;
    s(0, 0) = d[0];
    s(1, 1) = d[1];
    s(2, 2) = d[2];
    s(0, 1) = s(1, 0) = o[0];
    s(0, 2) = s(2, 0) = o[1];
    s(1, 2) = s(2, 1) = o[2];
    return s;
  }

 private:
  std::size_t index(int i, int j, int z) const { return (static_cast<std::size_t>(i) * planes_ + j) * depth_planes_ + z; }
  int planes_, depth_planes_;
  std::vector<float> rho_;
  std::unique_ptr<openvdb::Vec3DGrid::ConstAccessor> diag_, off_;
};

// A layer's density is the same across each voxel plane (stored voxels).
bool laterally_uniform(const openvdb::FloatGrid& grid) {
  auto acc = grid.getConstAccessor();
  for (auto it = grid.cbeginValueOn(); it; ++it)
    if (*it != acc.getValue(openvdb::Coord(0, 0, it.getCoord().z()))) return false;
  return true;
}

// Sliding maxima on a periodic row of m elements (element k at in + k stride,
// `lanes` contiguous doubles, each lane on its own): out[c stride] = max over
// in[((c + s b) mod m) stride], b in [0, w) (s = +1 or -1, w <= m), in O(m)
// whatever w (van Herk 1992, Gil & Werman 1993): the row unrolled so each
// window is [c, c + w) of it, maxima from each block of w's start (pre) and to
// its end (suf); a window spans at most two blocks. Lanes let a pass along y
// read whole rows (strips of columns), not one column at a stride of a row.
// The maximum of a set of doubles is exact in any order, so this equals the
// direct maximum bit for bit.
struct WindowMax {
  std::vector<double> pre, suf;
  void operator()(const double* in, std::ptrdiff_t stride, int m, int w, int s, double* out, int lanes = 1) {
    const int len = m + w - 1;
    pre.resize(static_cast<std::size_t>(len) * lanes);
    suf.resize(static_cast<std::size_t>(len) * lanes);
    const int k0 = s > 0 ? 0 : m - (w - 1);  // the element at t = 0 (s = -1: window c ends at c)
    const auto at = [&](int t) {
      const int k = k0 + t;  // < 2m
      return in + (k >= m ? k - m : k) * stride;
    };
    for (int b = 0; b < len; b += w) {  // the blocks of w
      const int e = std::min(b + w, len) - 1;
      double* p = pre.data() + static_cast<std::size_t>(b) * lanes;
      std::copy(at(b), at(b) + lanes, p);
      for (int t = b + 1; t <= e; ++t, p += lanes)
        for (int l = 0; l < lanes; ++l) p[lanes + l] = std::max(p[l], at(t)[l]);
      double* q = suf.data() + static_cast<std::size_t>(e) * lanes;
      std::copy(at(e), at(e) + lanes, q);
      for (int t = e - 1; t >= b; --t, q -= lanes)
        for (int l = 0; l < lanes; ++l) q[l - lanes] = std::max(q[l], at(t)[l]);
    }
    for (int c = 0; c < m; ++c)
      for (int l = 0; l < lanes; ++l)
        out[c * stride + l] = std::max(suf[static_cast<std::size_t>(c) * lanes + l], pre[static_cast<std::size_t>(c + w - 1) * lanes + l]);
  }
};

// Linear interpolation, exact at t = 0 and t = 1.
double lerp(double a, double b, double t) { return (1 - t) * a + t * b; }

// Bounds of the interpolated field over lateral cell (ci, cj) of m per tile side
// (cell ci spans voxels [ci n / m, (ci + 1) n / m]) and the voxel interval
// [z, z + 1] in depth. In each voxel cell the field is multilinear, so its least
// and greatest values over the part of the cell clipped to the voxel cell are at
// that part's corners: the voxels' bilinear interpolant there, on both voxel
// planes, the column past the last one read as stored (column N) and, on the
// tile's edge itself, wrapped (column 0: a lookup there wraps to x = 0).
Bounds cell_bounds(LayerReader& read, int n, int m, int ci, int cj, int z, bool s_varies) {
  Bounds c;
  // The voxel cells the cell overlaps along an axis, with the clipped part's
  // ends in the voxel cell (units of 1 / m voxel: the cell is [a n, (a + 1) n]).
  const auto overlap = [n, m](int a, int v, double t[2]) {
    t[0] = (std::max(a * n, v * m) - v * m) / static_cast<double>(m);
    t[1] = (std::min((a + 1) * n, (v + 1) * m) - v * m) / static_cast<double>(m);
  };
  for (int vj = cj * n / m; vj * m < (cj + 1) * n; ++vj)
    for (int vi = ci * n / m; vi * m < (ci + 1) * n; ++vi) {
      double tx[2], ty[2];
      overlap(ci, vi, tx);
      overlap(cj, vj, ty);
      // Away from the tile's edge both neighbours are the same column: read it once.
      const int j1s[2] = {vj + 1, (vj + 1) % n}, i1s[2] = {vi + 1, (vi + 1) % n};
      const int nj = j1s[1] == j1s[0] ? 1 : 2, ni = i1s[1] == i1s[0] ? 1 : 2;
      for (int zz = z; zz <= z + 1; ++zz)
        for (int b = 0; b < nj; ++b)
          for (int a = 0; a < ni; ++a) {
            const int j1 = j1s[b], i1 = i1s[a];
            const double v00 = read.density(vi, vj, zz), v10 = read.density(i1, vj, zz);
            const double v01 = read.density(vi, j1, zz), v11 = read.density(i1, j1, zz);
            for (const double y : ty)
              for (const double x : tx) {
                if ((i1 != vi + 1 && x < 1) || (j1 != vj + 1 && y < 1)) continue;  // wrapped: read on the tile's edge only
                const double v = lerp(lerp(v00, v10, x), lerp(v01, v11, x), y);
                c.lo = std::min(c.lo, v);
                c.hi = std::max(c.hi, v);
              }
            if (s_varies)
              for (const int j : {vj, j1})
                for (const int i : {vi, i1})
                  c.sigma = std::max(c.sigma, std::sqrt(std::max(0.0, largest_eigenvalue(read.matrix(i, j, zz)))));
          }
    }
  return c;
}

}  // namespace

std::vector<LayerMajorants> build_majorants(const DensityGrids& g, int lateral_block, int reach) {
  const SlabGeometry& geo = g.geometry();
  const int n = geo.grid.lateral_voxels, nz = geo.grid.depth_voxels;
  std::vector<LayerMajorants> out;
  double top = 0;
  for (std::size_t k = 0; k < geo.layers.size(); ++k) {
    const double bottom = top + geo.layers[k].thickness, hz = geo.layers[k].thickness / nz;
    LayerMajorants L;
    LayerReader read(g, k);
    if (g.has_sggx(k)) {
      const sggx::Mat3 s0 = read.matrix(0, 0, 0);
      L.one_s = all_active_equal(*g.s_diag(k), openvdb::Vec3d(s0(0, 0), s0(1, 1), s0(2, 2))) &&
                all_active_equal(*g.s_offdiag(k), openvdb::Vec3d(s0(0, 1), s0(0, 2), s0(1, 2)));
      L.s_varies = !L.one_s;
      if (L.one_s) L.s = sggx::from_matrix(s0);
    }
    // The largest factor(w) (1 if S varies: hi holds sigma then).
    const double max_factor = L.one_s ? std::sqrt(std::max(0.0, largest_eigenvalue(read.matrix(0, 0, 0)))) : 1.0;
    const int m = laterally_uniform(*g.grids()[k]) ? 1 : lateral_block > 0 ? n / lateral_block : n * kSubdivision;
    L.lateral = m;
    L.cell_size = geo.grid.tile / m;
    L.inv_cell_size = m / geo.grid.tile;
    // Bounds per voxel interval in depth (r = 0 at the top) and lateral cell.
    std::vector<Bounds> fine(static_cast<std::size_t>(nz) * m * m);
    for (int r = 0; r < nz; ++r)
      for (int cj = 0; cj < m; ++cj)
        for (int ci = 0; ci < m; ++ci)
          fine[(static_cast<std::size_t>(r) * m + cj) * m + ci] = cell_bounds(read, n, m, ci, cj, nz - r - 1, L.s_varies);
    // Depth cells: runs of voxel intervals whose bounds stay narrow in every column.
    const std::size_t row = static_cast<std::size_t>(m) * m;
    L.faces.push_back(top);
    std::vector<Run> run(row), wider(row);  // (reused: no allocation per voxel interval)
    for (int r0 = 0; r0 < nz;) {
      std::fill(run.begin(), run.end(), Run());
      for (std::size_t c = 0; c < row; ++c) run[c].add(fine[r0 * row + c]);
      int r1 = r0 + 1;
      for (; r1 < nz; ++r1) {
        wider = run;
        bool narrow = true;
        for (std::size_t c = 0; c < row; ++c) {
          wider[c].add(fine[r1 * row + c]);
          narrow = narrow && wider[c].narrow();
        }
        if (!narrow) break;
        std::swap(run, wider);
      }
      double row_hi = 0, row_lo = INFINITY;
      for (const Run& c : run) {
        L.hi.push_back(c.all.hi * (L.s_varies ? c.all.sigma : 1.0) * (1 + kMargin));
        L.lo.push_back(L.s_varies ? 0.0 : c.all.lo * (1 - kMargin));
        row_hi = std::max(row_hi, L.hi.back());
        row_lo = std::min(row_lo, L.lo.back());
      }
      L.row_hi.push_back(row_hi);
      L.row_lo.push_back(row_lo);
      L.faces.push_back(r1 == nz ? bottom : bottom - (nz - r1) * hz);
      r0 = r1;
    }
    if (m > 1) {  // per quadrant of the direction: the max over the (r + 1)^2 cells ahead, wrapped
      // Automatic reach: the cells in a mean free path at the mean majorant.
      double mean_hi = 0;
      for (const double h : L.hi) mean_hi += h / static_cast<double>(L.hi.size());
      const double free_path_cells = 1 / (mean_hi * max_factor * L.cell_size);
      const int r = L.reach = std::clamp(reach > 0 ? reach : static_cast<int>(std::lround(std::min(free_path_cells, 1e6))), 1, m - 1);
      // Box shapes (cells ahead along x, along y): square, then narrower across
      // the direction's major axis, for flights whose path over r + 1 cells along
      // it stays in a narrower band (free_flight.cpp).
      const int narrow[2] = {std::max(1, (r + 3) / 4), std::max(1, (r + 1) / 2)};
      L.box_reach = {{{r, r}, {r, narrow[1]}, {r, narrow[0]}, {narrow[1], r}, {narrow[0], r}}};
      L.narrow_reach[0] = narrow[0];
      L.narrow_reach[1] = narrow[1];
      const std::size_t cells = L.hi.size();
      L.ahead_hi.resize(4 * L.box_reach.size() * cells);
      double least = INFINITY;
      for (const double h : L.hi) least = h > 0 ? std::min(least, h) : least;
      L.ahead_levels = geometric_levels(*std::max_element(L.hi.begin(), L.hi.end()), least);
      // One table per shape and quadrant, each on its own (the same bits on any thread count).
      tbb::parallel_for(0, 4 * static_cast<int>(L.box_reach.size()), [&](int table) {
        const int shape = table / 4, q = table % 4;
        const int rx = L.box_reach[shape][0], ry = L.box_reach[shape][1], sx = q & 1 ? -1 : 1, sy = q & 2 ? -1 : 1;
        constexpr int kStrip = 16;  // columns per pass along y
        std::vector<double> along_x(row), box(row);  // max over the rx + 1 cells from each cell along x, then the box's
        WindowMax window;
        unsigned char* ahead = L.ahead_hi.data() + table * cells;
        for (std::size_t z = 0; z < L.row_hi.size(); ++z) {
          const double* hi = L.hi.data() + z * row;
          for (int cj = 0; cj < m; ++cj) window(hi + cj * m, 1, m, rx + 1, sx, along_x.data() + cj * m);
          for (int ci = 0; ci < m; ci += kStrip) window(along_x.data() + ci, m, m, ry + 1, sy, box.data() + ci, std::min(kStrip, m - ci));
          for (std::size_t c = 0; c < row; ++c) ahead[z * row + c] = level_above(box[c], L.ahead_levels);
        }
      });
    }
    out.push_back(std::move(L));
    top = bottom;
  }
  return out;
}

}  // namespace mcref::volume
