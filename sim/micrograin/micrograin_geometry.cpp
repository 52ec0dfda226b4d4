#include "sim/micrograin/micrograin_geometry.h"

#include <cmath>

#include "models/core/vec.h"

namespace mcref {

double MicrograinGeometry::c() const { return radius * std::sqrt(beta_x * beta_y); }
double MicrograinGeometry::r_x() const { return c() / beta_x; }
double MicrograinGeometry::r_y() const { return c() / beta_y; }
double MicrograinGeometry::density() const { return unit_density() / (r_x() * r_y()); }
double MicrograinGeometry::unit_density() const { return -std::log1p(-tau0) / kPi; }

}  // namespace mcref
