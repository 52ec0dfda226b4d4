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
  // The tile must hold the grains' footprints with room to spare (> 2 diameters).
  const double min_tile = 4.0 * std::fmax(m.r_x(), m.r_y()) / m.radius;
  m.tile = g.number("tile", {min_tile, 1e5, true, false}, 200.0);
  // Grain count must stay reasonable (about 1e8 at most).
  const double expected = m.unit_density() * (m.tile * m.radius / m.r_x()) * (m.tile * m.radius / m.r_y());
  if (expected > 1e8) g.fail("tile", "gives ~" + std::to_string(static_cast<long long>(expected)) +
                                         " grains; at most 1e8 are allowed");
}

// A ray at theta from the normal crosses the grains' height c over a
// horizontal distance c tan(theta), wrapping round the periodic tile that many
// tile sides: a measure's cost grows without bound toward grazing angles, so
// its directions are refused past kMaxTileCrossings.
void check_micrograin_directions(const Experiment& e) {
  constexpr double kMaxTileCrossings = 100;
  const MicrograinGeometry& g = e.micrograin;
  const double side = g.tile * g.radius / std::fmax(g.r_x(), g.r_y());  // in horizontal radii
  const double c = g.c() / std::fmax(g.r_x(), g.r_y());
  const double theta_max = std::atan(kMaxTileCrossings * side / c);
  for (std::size_t k = 0; k < e.measures.size(); ++k) {
    const Measure& m = e.measures[k];
    for (const auto& [key, angles] : {std::pair{"theta_i_deg", &m.theta_i}, std::pair{"theta_o_deg", &m.theta_o}})
      for (double t : *angles)
        if (t > theta_max)
          throw ConfigError(e.file, "measure." + std::to_string(k) + "." + key,
                            exact_text(t * 180 / kPi) + " is too grazing: its rays would cross the tile more than " +
                                std::to_string(static_cast<int>(kMaxTileCrossings)) + " times; at most " +
                                exact_text(theta_max * 180 / kPi) + " deg with this tile (a larger geometry.tile allows more)");
  }
}

}  // namespace mcref
