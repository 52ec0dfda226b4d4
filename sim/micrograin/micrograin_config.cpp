// The [geometry] keys of a micrograin field (kind = "micrograin"); every error
// names the key and its allowed range. The [material] keys are read in
// micrograin_materials.cpp.
#include <cmath>
#include <limits>
#include <string>

#include "sim/experiment/experiment_parts.h"

namespace mcref {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

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
  m.radius = g.number("radius", {0, kInf, true, true}, 1.0);
  // The tile must hold the grains' footprints with room to spare (> 2 diameters).
  const double min_tile = 4.0 * std::fmax(m.r_x(), m.r_y()) / m.radius;
  m.tile = g.number("tile", {min_tile, 1e5, true, false}, 200.0);
  // Grain count must stay reasonable (about 1e8 at most).
  const double expected = m.unit_density() * (m.tile * m.radius / m.r_x()) * (m.tile * m.radius / m.r_y());
  if (expected > 1e8) g.fail("tile", "gives ~" + std::to_string(static_cast<long long>(expected)) +
                                         " grains; at most 1e8 are allowed");
}

}  // namespace mcref
