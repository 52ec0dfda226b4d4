// The [geometry] keys of a micrograin field (kind = "micrograin"); every error
// names the key and its allowed range. The [material] keys are read in
// micrograin_materials.cpp.
#include <cmath>
#include <string>
#include <utility>

#include "sim/experiment/experiment_parts.h"

namespace mcref {

void read_micrograin_geometry(TomlReader& g, Experiment& e) {
  MicrograinGeometry& m = e.micrograin;
  m.tau0 = g.number("tau0", {0, 1, true, true});
  const Range beta_range{0, 100, true, false};
  if (g.has("beta")) {
    if (g.has("beta_x") || g.has("beta_y")) g.fail("beta", "give either beta or beta_x/beta_y, not both");
    m.beta_x = m.beta_y = g.number("beta", beta_range);
  } else if (g.has("beta_x") || g.has("beta_y")) {
    m.beta_x = g.number("beta_x", beta_range);
    m.beta_y = g.number("beta_y", beta_range);
  } else {
    g.fail("beta", "is required (or beta_x and beta_y), a number in " + beta_range.text());
  }
  e.isotropic = !m.anisotropic();
  // Lengths set units only: tables are bit-identical for any radius in this
  // range (tested at its ends). Beyond it the unit-space ray directions
  // (components ~ 1/radius) leave float's exact range in Embree.
  m.radius = g.number("radius", {1e-9, 1e9, false, false}, 1.0);
  // Bounds for the grain's semi-axes c, r_x, r_y too, a decade past what the
  // radius range reaches at beta ~ 1 (beta = 1e-20 made c = 1e-20: unit-space
  // directions beyond Embree's range, an assertion).
  for (const auto& [name, length] : {std::pair{"c", m.c()}, std::pair{"r_x", m.r_x()}, std::pair{"r_y", m.r_y()}})
    if (!(length >= 1e-10 && length <= 1e10))
      g.fail(g.has("beta") ? "beta" : "beta_y", "gives the grains a semi-axis " + std::string(name) + " = " + exact_text(length) +
                                                    " (c = radius sqrt(beta_x beta_y), r_x = c / beta_x, r_y = c / beta_y); each must be in [1e-10, 1e10]");
  // The tile must hold the grains' footprints with room to spare (> 2 diameters);
  // the default too (200 was below it for beta_x / beta_y > 1e4).
  const double min_tile = 4.0 * std::fmax(m.r_x(), m.r_y()) / m.radius;
  const Range tile_range{min_tile, 1e5, true, false};
  m.tile = g.number("tile", tile_range, 200.0);
  if (!tile_range.contains(m.tile))
    g.fail("tile", "is not given, and its default 200 is outside " + tile_range.text() + " for these grains; give a tile in it");
  // Grain count must stay reasonable (about 1e8 at most).
  const double expected = m.unit_density() * (m.tile * m.radius / m.r_x()) * (m.tile * m.radius / m.r_y());
  if (expected > 1e8) g.fail("tile", "gives ~" + std::to_string(static_cast<long long>(expected)) +
                                         " grains; at most 1e8 are allowed");
}

// A ray at theta from the normal crosses the grains' height c over a
// horizontal distance c tan(theta). On the periodic tile, once that distance
// plus a grain's width reaches the tile side, the ray can meet a grain again
// (its periodic copy): the visibility it measures is no longer the plane's
// Boolean model's exp(-rho area) (LRPB23 Eq. 21-22; tau+ at 89 deg on a tile
// of 40 radii, 1.4 sides, was 0.678 +- 0.013 against 0.776). So directions are
// refused past c tan(theta) = side - 2 max(r_x, r_y). Likewise p1's distances
// (LRPB23 Eq. 8-10): beyond half the tile the nearest centre is a copy.
void check_micrograin_directions(const Experiment& e) {
  const MicrograinGeometry& g = e.micrograin;
  const double r = std::fmax(g.r_x(), g.r_y());
  const double side = g.tile * g.radius / r;  // in the larger horizontal radius
  const double c = g.c() / r;
  const double theta_max = std::atan((side - 2) / c);
  for (std::size_t k = 0; k < e.measures.size(); ++k) {
    const Measure& m = e.measures[k];
    const std::string key = "measure." + std::to_string(k) + ".";
    if (m.quantity == "p1") {
      const double half = 0.5 * g.tile * g.radius / r;  // half the shorter unit-space side, in grain radii
      if (m.r_max > half)
        throw ConfigError(e.file, key + "r_max", "= " + exact_text(m.r_max) + " reaches beyond half the tile (" +
                                                     exact_text(half) + " grain radii), where the nearest centre is a periodic copy; "
                                                     "lower r_max or enlarge geometry.tile");
      continue;
    }
    if (m.quantity == "phi_conditional") continue;  // its theta_i is a unit-space angle; no ray is traced
    for (const auto& [name, angles] : {std::pair{"theta_i_deg", &m.theta_i}, std::pair{"theta_o_deg", &m.theta_o}})
      for (double t : *angles)
        if (t > theta_max)
          throw ConfigError(e.file, key + name,
                            exact_text(t * 180 / kPi) + " is too grazing for this tile: its rays would meet a grain's periodic "
                                "copy (c tan(theta) + 2 radii > the tile side); at most " +
                                exact_text(theta_max * 180 / kPi) + " deg with this tile (a larger geometry.tile allows more)");
  }
}

}  // namespace mcref
