// The per-cell majorants of the OpenVDB slab (sim/slab/majorant_grid.h)
// against brute force: at random points of every cell (on its faces too, and
// in lateral images of the tile) and random directions, the extinction
// rho(x) sigma(w; S(x)) read through GridLookup stays at or below the cell's
// majorant hi * factor(w), and rho(x) at or above its minorant lo (cells half a
// voxel column wide, the default, and one column wide); so does the
// density of the dense copy the flights read (VoxelDensity). The voxels
// are random, the stored periodic seam column included, and so is S in one
// layer. Also: the dense copy agrees with OpenVDB's sampler; bit-identical
// tables for 1 and 2 threads on the grid path, and walk sums on the lateral
// path; the boxes' majorants (ahead_hi) against brute force; lateral flights
// (boxes of cells ahead of the photon) that agree with flights against one
// cell per layer.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>

#include <tbb/global_control.h>

#include "models/core/rng.h"
#include "models/core/warp.h"
#include "sim/experiment/experiment.h"
#include "sim/parallel/run_chunks.h"
#include "sim/slab/density_grid.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/voxel_density.h"
#include "sim/slab/walk.h"
#include "sim/tally/brdf_tally.h"
#include "tests/sim/slab/test_slab_helpers.h"

using namespace mcref;

namespace {

const char* kGeometry = R"([geometry]
kind = "slab"
backend = "openvdb"
tile = 2.0
lateral_voxels = 5
depth_voxels = 6
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.3
orientation_deg = [60, 30]
thickness = 0.5
density = 3.0
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.2
orientation_deg = [20, 110]
thickness = 1.0
density = 1.5
profile = "linear"
profile_top = 0.3
profile_bottom = 1.0
[[geometry.layer]]
phase = "isotropic"
thickness = 0.7
density = 2.0
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 1
)";

// Layer 0: random density and random positive definite S per voxel; layer 1 as
// built (linear profile, one S); layer 2: random density per voxel.
std::unique_ptr<volume::DensityGrids> random_grids(const SlabGeometry& g, Rng& rng) {
  auto grids = std::make_unique<volume::DensityGrids>(g);
  const int n = g.grid.lateral_voxels, nz = g.grid.depth_voxels;
  for (int k : {0, 2}) {
    auto rho = grids->grids()[k]->getAccessor();
    for (int z = 0; z <= nz; ++z)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) rho.setValue(openvdb::Coord(i, j, z), static_cast<float>(0.2 + 3 * rng.uniform()));
  }
  auto diag = grids->s_diag(0)->getAccessor();
  auto off = grids->s_offdiag(0)->getAccessor();
  for (int z = 0; z <= nz; ++z)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        double a[3][3];
        for (auto& row : a)
          for (double& v : row) v = 2 * rng.uniform() - 1;
        double s[3][3];  // A A^T + 0.05 I
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            s[r][c] = a[r][0] * a[c][0] + a[r][1] * a[c][1] + a[r][2] * a[c][2] + (r == c ? 0.05 : 0.0);
        diag.setValue(openvdb::Coord(i, j, z), openvdb::Vec3d(s[0][0], s[1][1], s[2][2]));
        off.setValue(openvdb::Coord(i, j, z), openvdb::Vec3d(s[0][1], s[0][2], s[1][2]));
      }
  return grids;
}

// A coordinate in [lo, hi]: often on a face or within rounding of it.
double in_range(double lo, double hi, Rng& rng) {
  const double u = rng.uniform();
  if (u < 0.1) return lo;
  if (u < 0.2) return hi;
  if (u < 0.3) return lo + (hi - lo) * 1e-12;
  if (u < 0.4) return hi - (hi - lo) * 1e-12;
  return lo + (hi - lo) * rng.uniform();
}

// Per path: reflectance (0 or 1), scattering events, depth of the first event
// (the bottom face if none); sums for their means and standard errors.
struct Moments {
  double n = 0, sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
  void add(int i, double v) { sum[i] += v, sq[i] += v * v; }
  double mean(int i) const { return sum[i] / n; }
  double var_mean(int i) const { return (sq[i] / n - mean(i) * mean(i)) / (n - 1); }
};

// Analog paths through the medium's flights (no tally), entering along -wi at a
// uniform point of the tile.
Moments flight_moments(const volume::SlabMedium& medium, Vec3 wi, int paths, std::uint64_t seed) {
  auto flight = volume::make_flight(medium);
  Rng rng(seed);
  Moments s;
  const double tile = medium.geometry().grid.tile;
  for (int path = 0; path < paths; ++path, ++s.n) {
    volume::Photon p;
    p.d = -wi;
    p.x = rng.uniform() * tile;
    p.y = rng.uniform() * tile;
    int events = 0;
    double first_depth = medium.bottom();
    for (;;) {
      const volume::Flight f = flight->fly(p, rng);
      if (f != volume::Flight::kCollision) {
        s.add(0, f == volume::Flight::kExitTop ? 1.0 : 0.0);
        break;
      }
      if (events++ == 0) first_depth = p.depth;
      const volume::ScatterSample sc = flight->scatter(medium.layers()[p.layer], p.layer, -p.d, rng);
      EXPECT_TRUE(sc.valid);
      p.d = sc.wo;
    }
    s.add(1, events);
    s.add(2, first_depth);
  }
  return s;
}

// Each of the three means within 4.5 combined standard errors.
void expect_same_moments(const Moments& a, const Moments& b, const std::string& what) {
  const char* names[3] = {"reflectance", "events per path", "first event depth"};
  for (int i = 0; i < 3; ++i) {
    const double z = (a.mean(i) - b.mean(i)) / std::sqrt(a.var_mean(i) + b.var_mean(i));
    EXPECT_LT(std::fabs(z), 4.5) << names[i] << ": " << what << " " << a.mean(i) << ", one cell " << b.mean(i);
  }
}

// Flights against one cell per layer and depth run (lateral_block =
// lateral_voxels) and against boxes of each reach (0: the automatic one) of
// cells of fine_block voxel columns (0: the default, half a column) agree
// (expect_same_moments); seeds: `seed` for one cell, seed + 1, ... for the boxes.
void expect_boxes_agree_with_one_cell(const std::function<std::unique_ptr<volume::SlabMedium>(int, int)>& medium,
                                      const SlabGeometry& g, Vec3 wi, int paths, std::uint64_t seed,
                                      std::initializer_list<int> reaches, int fine_block = 1) {
  const auto coarse = medium(g.grid.lateral_voxels, 0);
  for (const volume::LayerMajorants& M : coarse->majorants()) ASSERT_EQ(M.lateral, 1);
  const Moments b = flight_moments(*coarse, wi, paths, seed);
  for (const int reach : reaches) {
    const auto fine = medium(fine_block, reach);
    std::string what = "boxes of reach";
    for (const volume::LayerMajorants& M : fine->majorants())
      if (M.lateral > 1) what += " " + std::to_string(M.reach);
    expect_same_moments(flight_moments(*fine, wi, paths, ++seed), b, what);
  }
}

// A laterally varying layer: density times 1 + 0.5 cos(2 pi x) cos(2 pi y) on a
// unit tile of 16 x 16 voxel columns (SGGX surface-like, alpha 0.5), with
// majorant cells of `block` columns and boxes of `reach` (0: automatic), on
// slab_test::lateral_grid_experiment's layer.

std::unique_ptr<volume::SlabMedium> cosine_lateral_medium(const SlabGeometry& g, int block, int reach) {
  auto grids = std::make_unique<volume::DensityGrids>(g);
  const int n = g.grid.lateral_voxels;
  for (auto it = grids->grids()[0]->beginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    it.setValue(*it * static_cast<float>(1 + 0.5 * std::cos(2 * kPi * c.x() / n) * std::cos(2 * kPi * c.y() / n)));
  }
  return std::make_unique<volume::SlabMedium>(g, std::move(grids), block, reach);
}

}  // namespace

TEST(SlabMajorants, BoundTheExtinctionInEveryCell) {
  const Experiment ex = parse_experiment(kGeometry, "m.toml");
  const SlabGeometry& g = ex.slab;
  for (const int block : {0, 1}) {  // cells of half a voxel column (the default) and of one column
    Rng rng(2024);
    const volume::SlabMedium medium(g, random_grids(g, rng), block);
    const std::vector<volume::LayerMajorants>& maj = medium.majorants();
    ASSERT_EQ(maj.size(), 3u);
    EXPECT_TRUE(maj[0].s_varies);
    EXPECT_TRUE(maj[1].one_s);
    EXPECT_EQ(maj[1].lateral, 1);  // depth profile only
    EXPECT_GT(maj[1].depth_cells(), 1);
    EXPECT_EQ(maj[2].lateral, (block == 0 ? volume::kSubdivision : 1) * g.grid.lateral_voxels);
    volume::GridLookup lookup(*medium.grids());
    const double tile = g.grid.tile;
    std::size_t samples = 0, over = 0, under = 0;
    std::ostringstream first;
    for (int k = 0; k < 3; ++k) {
      const volume::LayerMajorants& M = maj[k];
      const int m = M.lateral;
      EXPECT_EQ(M.faces.front(), medium.layers()[k].top);
      EXPECT_EQ(M.faces.back(), medium.layers()[k].bottom);
      for (int cz = 0; cz < M.depth_cells(); ++cz)
        for (int cj = 0; cj < m; ++cj)
          for (int ci = 0; ci < m; ++ci) {
            const std::size_t cell = (static_cast<std::size_t>(cz) * m + cj) * m + ci;
            for (int s = 0; s < 400; ++s, ++samples) {
              // A point of the cell, in the tile or one of its lateral images.
              const double x = in_range(ci * M.cell_size, (ci + 1) * M.cell_size, rng) + tile * std::floor(7 * rng.uniform() - 3);
              const double y = in_range(cj * M.cell_size, (cj + 1) * M.cell_size, rng) + tile * std::floor(7 * rng.uniform() - 3);
              const double depth = in_range(M.faces[cz], M.faces[cz + 1], rng);
              const double u1 = rng.uniform(), u2 = rng.uniform();
              const Vec3 w = sample_uniform_sphere(u1, u2);
              double rho = 0, sigma = 1;
              if (k == 2) {
                rho = lookup.density(k, x, y, depth);
              } else {
                sggx::Mat3 S;
                rho = lookup.density_and_sggx(k, x, y, depth, S);
                sigma = std::sqrt(sggx::quadratic_form(S, w));
              }
              const double dense = medium.voxels()->density(k, x, y, depth);
              const bool above = std::max(rho, dense) * sigma > M.hi[cell] * M.factor(w),
                         below = !M.s_varies && std::min(rho, dense) < M.lo[cell];
              if ((above || below) && over + under == 0)
                first << "layer " << k << " cell " << cell << " at (" << x << ", " << y << ", " << depth << "): rho "
                      << rho << " (dense " << dense << ") sigma " << sigma << " hi*factor " << M.hi[cell] * M.factor(w) << " lo " << M.lo[cell];
              over += above;
              under += below;
            }
          }
    }
    EXPECT_GT(samples, 10000u);
    EXPECT_EQ(over, 0u) << first.str();
    EXPECT_EQ(under, 0u) << first.str();
  }
}

// The box majorants the lateral flights read (ahead_hi) are, for every box
// shape, quadrant and cell, the max of hi over exactly the box the flight uses
// (the cell and the rx cells ahead of it along x and ry along y, in the
// quadrant's directions, wrapped around the tile; brute force, cell by cell),
// rounded up to the least of the layer's levels above it, at most 5 % above it
// (to the rounding of the levels' powers).
// On the random layer and the cosine layer, cells of half a column and of one;
// the cosine layer also with the widest boxes (reach m - 1: a window of the
// whole row, computed by sliding maxima in majorant_grid.cpp).
TEST(SlabMajorants, BoxMajorantsAreTheMaxOverTheirBoxes) {
  const Experiment random = parse_experiment(kGeometry, "m.toml");
  const Experiment lateral = slab_test::lateral_grid_experiment();
  std::size_t boxes = 0, uneven = 0;
  for (const int block : {0, 1}) {
    Rng rng(2025);
    const volume::SlabMedium stack(random.slab, random_grids(random.slab, rng), block);
    const auto cosine = cosine_lateral_medium(lateral.slab, block, 0);
    const auto widest = cosine_lateral_medium(lateral.slab, block, 1 << 20);  // clamped to m - 1
    ASSERT_EQ(widest->majorants()[0].reach, widest->majorants()[0].lateral - 1);
    for (const volume::LayerMajorants* M : {&stack.majorants()[2], &cosine->majorants()[0], &widest->majorants()[0]}) {
      const int m = M->lateral, r = M->reach;
      ASSERT_GT(m, 1);
      ASSERT_GE(r, 1);
      // The square, then long along x, then long along y, each narrower across.
      EXPECT_EQ(M->box_reach[0], (std::array<int, 2>{r, r}));
      for (int shape = 1; shape < 5; ++shape) {
        const int along = shape < 3 ? 0 : 1;
        EXPECT_EQ(M->box_reach[shape][along], r);
        EXPECT_LE(M->box_reach[shape][1 - along], r);
      }
      const std::size_t cells = M->hi.size();
      ASSERT_EQ(M->ahead_hi.size(), 20 * cells);
      for (int shape = 0; shape < 5; ++shape)
        for (int q = 0; q < 4; ++q) {
          const int rx = M->box_reach[shape][0], ry = M->box_reach[shape][1];
          const int sx = q & 1 ? -1 : 1, sy = q & 2 ? -1 : 1;  // q = [w_x < 0] + 2 [w_y < 0]
          for (int cz = 0; cz < M->depth_cells(); ++cz)
            for (int cj = 0; cj < m; ++cj)
              for (int ci = 0; ci < m; ++ci, ++boxes) {
                double best = 0;
                for (int a = 0; a <= ry; ++a)
                  for (int b = 0; b <= rx; ++b) {
                    const int i = ((ci + sx * b) % m + m) % m, j = ((cj + sy * a) % m + m) % m;
                    best = std::max(best, M->hi[(static_cast<std::size_t>(cz) * m + j) * m + i]);
                  }
                const std::size_t cell = (static_cast<std::size_t>(cz) * m + cj) * m + ci;
                const int level = M->ahead_hi[(static_cast<std::size_t>(shape) * 4 + q) * cells + cell];
                const double ahead = M->ahead_levels[level];
                ASSERT_TRUE(ahead >= best && (level == 0 || M->ahead_levels[level - 1] < best) &&
                            (best < M->ahead_levels[1] || ahead <= 1.05 * (1 + 1e-12) * best)) << "shape " << shape << " (" << rx << ", " << ry << ") quadrant " << q
                                       << " cell " << ci << ", " << cj << ", " << cz;
                uneven += best > M->hi[cell];
              }
        }
    }
  }
  EXPECT_GT(boxes, 20000u);
  EXPECT_GT(uneven, boxes / 2) << "boxes whose max is their own cell's test little";
}

// The dense copy of the density voxels the flights read (VoxelDensity) agrees
// with OpenVDB's trilinear sampler (GridLookup::density, which rounds each of
// its 7 interpolations to float) to 1e-6 of the largest voxel (3.2) at random
// points of every layer, in lateral images of the tile, on voxel planes, within
// rounding of them, on the tile's edges and on the layer's faces. The voxels are
// random, with the seam columns repeating columns 0 as DensityGrids stores them
// (with a seam that does not, a point on the tile's edge may read either; the
// test above checks that the majorants bound both).
TEST(SlabMajorants, DenseDensityAgreesWithTheOpenVdbSampler) {
  const Experiment ex = parse_experiment(kGeometry, "m.toml");
  const SlabGeometry& g = ex.slab;
  Rng rng(11);
  auto grids = random_grids(g, rng);
  const int n = g.grid.lateral_voxels, nz = g.grid.depth_voxels;
  for (const openvdb::FloatGrid::Ptr& grid : grids->grids()) {
    auto acc = grid->getAccessor();
    for (int z = 0; z <= nz; ++z)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
          if (i == n || j == n) acc.setValue(openvdb::Coord(i, j, z), acc.getValue(openvdb::Coord(i % n, j % n, z)));
  }
  const volume::VoxelDensity dense(*grids);
  volume::GridLookup lookup(*grids);
  const double tile = g.grid.tile, h = tile / n;
  std::size_t samples = 0, differ = 0;
  double top = 0;
  for (int k = 0; k < 3; ++k) {
    const double thickness = g.layers[k].thickness, hz = thickness / nz;
    // A coordinate on a voxel plane, within rounding of one, or anywhere.
    const auto coordinate = [&](double step, int planes, double lo) {
      const double u = rng.uniform(), plane = lo + step * std::floor(rng.uniform() * (planes + 1));
      if (u < 0.2) return plane;
      if (u < 0.3) return std::nextafter(plane, -INFINITY);
      if (u < 0.4) return std::nextafter(plane, INFINITY);
      return lo + step * planes * rng.uniform();
    };
    for (int s = 0; s < 100000; ++s, ++samples) {
      const double x = coordinate(h, n, 0) + tile * std::floor(7 * rng.uniform() - 3);
      const double y = coordinate(h, n, 0) + tile * std::floor(7 * rng.uniform() - 3);
      const double depth = std::fmin(top + thickness, std::fmax(top, coordinate(hz, nz, top)));
      const double a = dense.density(k, x, y, depth), b = lookup.density(k, x, y, depth);
      if (!(std::fabs(a - b) <= 1e-6 * 3.2) && ++differ == 1)
        ADD_FAILURE() << "layer " << k << " at (" << x << ", " << y << ", " << depth << "): dense " << a << ", sampler " << b;
    }
    top += thickness;
  }
  EXPECT_EQ(samples, 300000u);
  EXPECT_EQ(differ, 0u);
}

// The majorant of a cell is the bound of the field, not more: at its corners
// the field reaches hi / (1 + kMargin) (layer 2: sigma = 1, random voxels, so
// one depth cell per voxel interval; laterally the default cells, half a voxel
// column wide: their corners are the voxel corners and the voxel cells' midpoints). The last column's far corner is read both just
// before the tile's edge (the stored seam column) and on it (wrapped: column 0).
TEST(SlabMajorants, CellMajorantIsReachedInTheCell) {
  const Experiment ex = parse_experiment(kGeometry, "m.toml");
  Rng rng(7);
  const volume::SlabMedium medium(ex.slab, random_grids(ex.slab, rng));
  const volume::LayerMajorants& M = medium.majorants()[2];
  volume::GridLookup lookup(*medium.grids());
  const int m = M.lateral;
  for (int cz = 0; cz < M.depth_cells(); ++cz)
    for (int cj = 0; cj < m; ++cj)
      for (int ci = 0; ci < m; ++ci) {
        double best = 0;
        for (double fx : {0.0, 1 - 1e-12, 1.0})
          for (double fy : {0.0, 1 - 1e-12, 1.0})
            for (double fz : {0.0, 1.0})
              best = std::max(best, lookup.density(2, (ci + fx) * M.cell_size, (cj + fy) * M.cell_size,
                                                   M.faces[cz] + fz * (M.faces[cz + 1] - M.faces[cz])));
        const std::size_t cell = (static_cast<std::size_t>(cz) * m + cj) * m + ci;
        EXPECT_NEAR(best * (1 + volume::kMargin), M.hi[cell], 1e-6 * M.hi[cell]) << "cell " << cell;
      }
}

TEST(SlabMajorants, GridPathBitIdenticalForOneAndTwoThreads) {
  const Experiment ex = parse_experiment(R"([geometry]
kind = "slab"
backend = "openvdb"
depth_voxels = 8
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 3.0
profile = "linear"
profile_top = 0.5
profile_bottom = 1.5
albedo = [0.9, 0.8, 0.7]
[run]
seed = 9
batches = 3
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 20000
)", "test.toml");
  slab_test::expect_bit_identical_threads(ex);
}

// Delta tracking is exact for any majorant that bounds the extinction: on a
// laterally varying layer (density times 1 + 0.5 cos(2 pi x) cos(2 pi y) on a
// unit tile of 16 x 16 voxel columns, SGGX surface-like, alpha 0.5, albedo 1,
// theta_i = 60 deg), flights against one cell per layer (no boxes, 3x the null
// collisions) and against boxes of voxel-column cells ahead of the photon
// (reach 1, the automatic reach, 15: the whole tile) agree in the reflectance, the
// mean number of scattering events per path and the mean depth of the first
// event (the bottom face if none), each within 4.5 combined standard errors
// (2^17 paths each, seeds 7, 8, 9 for the boxes and 6 for one cell; the
// family of 9 fails by chance with probability < 7e-5).
TEST(SlabMajorants, LateralFlightsDoNotDependOnTheCellSize) {
  const Experiment ex = slab_test::lateral_grid_experiment();
  const SlabGeometry& g = ex.slab;
  const auto lateral_medium = [&](int block, int reach) { return cosine_lateral_medium(g, block, reach); };
  const auto automatic = lateral_medium(1, 0);
  ASSERT_EQ(automatic->majorants()[0].lateral, 16);
  EXPECT_EQ(automatic->majorants()[0].reach, 5);  // 16 cells per unit tile, mean free path about 1 / 3.3
  expect_boxes_agree_with_one_cell(lateral_medium, g, spherical_direction(60 * kPi / 180, 0.3), 1 << 17, 6, {1, 0, 15});
}

// Results do not depend on the thread count on the lateral path either (no
// TOML reaches it, so GridPathBitIdenticalForOneAndTwoThreads cannot): the
// walk's binned sums over 2^14 paths through the laterally varying medium
// above (theta_i = 50 deg, seed 11), in run_chunks' 4 chunks as simulate_slab
// runs them, are bit-identical on 1 and 2 threads.
TEST(SlabMajorants, LateralPathBitIdenticalForOneAndTwoThreads) {
  const Experiment ex = slab_test::lateral_grid_experiment();
  const auto medium = cosine_lateral_medium(ex.slab, 1, 0);
  ASSERT_EQ(medium->majorants()[0].lateral, 16);
  BrdfLayout layout;
  layout.transmission = true;
  layout.order1_classes = {"volume", "substrate"};
  const Vec3 wi = spherical_direction(50 * kPi / 180, 0);
  const auto sums = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    return run_chunks(1 << 14, layout.sums_size(), 11, [&](Rng& rng, std::uint64_t count, Sums& s) {
      BrdfAccumulator acc(layout, 0.0, s);
      auto flight = volume::make_flight(*medium);
      for (std::uint64_t n = 0; n < count; ++n) volume::walk(*medium, *flight, volume::WalkSettings{}, wi, rng, acc);
    });
  };
  const Sums one = sums(1), two = sums(2);
  double energy = 0;
  for (double v : one) energy += v;
  ASSERT_GT(energy, 0);  // not zero against zero
  EXPECT_EQ(one, two);
}

// The same on the random three-layer stack of the tests above (laterally varying
// density in layers 0 and 2, varying S in layer 0, a linear depth profile
// between them; 5 x 5 voxel columns on a tile of 2, albedo 1, theta_i = 40 deg):
// flights against boxes of reach 1, the automatic one and 4 (the whole tile)
// agree with flights against one cell per layer and depth run, through the
// layers' faces both ways (2^16 paths each, seeds 21-23 and 20; 9 comparisons,
// by chance all pass with probability > 1 - 7e-5).
TEST(SlabMajorants, BoxFlightsAgreeWithOneCellOnARandomStack) {
  const Experiment ex = parse_experiment(kGeometry, "m.toml");
  const SlabGeometry& g = ex.slab;
  const auto medium = [&](int block, int reach) {
    Rng rng(2024);
    return std::make_unique<volume::SlabMedium>(g, random_grids(g, rng), block, reach);
  };
  ASSERT_EQ(medium(1, 0)->majorants()[0].lateral, 5);
  ASSERT_EQ(medium(1, 0)->majorants()[2].lateral, 5);
  expect_boxes_agree_with_one_cell(medium, g, spherical_direction(40 * kPi / 180, 1.1), 1 << 16, 20, {1, 0, 4});
}

// The default cells, half a voxel column wide (their bounds read from the voxels'
// interpolant at their corners, majorant_grid.h), give flights that agree with one
// cell per layer and depth run, as LateralFlightsDoNotDependOnTheCellSize and
// BoxFlightsAgreeWithOneCellOnARandomStack check for voxel-column cells: on the
// cosine layer (theta_i = 60 deg, 2^17 paths each, seeds 30 for one cell and 31-33
// for boxes of reach 1, the automatic one and 31, the whole tile of 32 cells) and on
// the random stack (theta_i = 40 deg, 2^16 paths each, seeds 40 and 41-43, reaches
// 1, automatic and 9). 18 comparisons within 4.5 combined standard errors: all pass
// by chance with probability > 1 - 1.3e-4.
TEST(SlabMajorants, HalfVoxelCellFlightsAgreeWithOneCell) {
  const Experiment lateral = slab_test::lateral_grid_experiment();
  const auto cosine = [&](int block, int reach) { return cosine_lateral_medium(lateral.slab, block, reach); };
  ASSERT_EQ(cosine(0, 0)->majorants()[0].lateral, 32);
  expect_boxes_agree_with_one_cell(cosine, lateral.slab, spherical_direction(60 * kPi / 180, 0.3), 1 << 17, 30, {1, 0, 31}, 0);
  const Experiment stack = parse_experiment(kGeometry, "m.toml");
  const auto random_stack = [&](int block, int reach) {
    Rng rng(2024);
    return std::make_unique<volume::SlabMedium>(stack.slab, random_grids(stack.slab, rng), block, reach);
  };
  ASSERT_EQ(random_stack(0, 0)->majorants()[2].lateral, 10);
  expect_boxes_agree_with_one_cell(random_stack, stack.slab, spherical_direction(40 * kPi / 180, 1.1), 1 << 16, 40, {1, 0, 9}, 0);
}
