// Small helpers of SlabGeometry (sim/slab/slab_geometry.h).
#include <algorithm>
#include <cmath>

#include "sim/slab/slab_geometry.h"

namespace mcref {

double DensityProfile::at(double s) const {
  s = std::clamp(s, 0.0, 1.0);
  switch (kind) {
    case Kind::kConstant: return 1.0;
    case Kind::kLinear: return top + (bottom - top) * s;
    case Kind::kTable: break;
  }
  const double x = s * static_cast<double>(table.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(x), table.size() - 2);
  const double f = x - static_cast<double>(i);
  return table[i] + (table[i + 1] - table[i]) * f;
}

double DensityProfile::mean() const {
  switch (kind) {
    case Kind::kConstant: return 1.0;
    case Kind::kLinear: return 0.5 * (top + bottom);
    case Kind::kTable: break;
  }
  double s = 0;  // trapezoids of the piecewise-linear table
  for (std::size_t i = 0; i + 1 < table.size(); ++i) s += 0.5 * (table[i] + table[i + 1]);
  return s / static_cast<double>(table.size() - 1);
}

double DensityProfile::max() const {
  switch (kind) {
    case Kind::kConstant: return 1.0;
    case Kind::kLinear: return std::max(top, bottom);
    case Kind::kTable: break;
  }
  return *std::max_element(table.begin(), table.end());
}

bool SlabLayer::azimuthally_symmetric() const {
  if (varies_laterally) return false;
  if (!is_sggx()) return true;
  return std::fabs(orientation.x) < 1e-12 && std::fabs(orientation.y) < 1e-12;
}

double SlabGeometry::total_thickness() const {
  double t = 0;
  for (const SlabLayer& l : layers) t += l.thickness;
  return t;
}

bool SlabGeometry::conservative() const {
  for (const SlabLayer& l : layers) {
    if (l.albedo.r != 1 || l.albedo.g != 1 || l.albedo.b != 1) return false;
    if (l.is_sggx() && (l.f0.r != 1 || l.f0.g != 1 || l.f0.b != 1)) return false;
  }
  if (substrate.kind == SlabSubstrate::Kind::kNone) return true;
  return substrate.kind == SlabSubstrate::Kind::kLambertian && substrate.albedo.r == 1 && substrate.albedo.g == 1 &&
         substrate.albedo.b == 1;
}

}  // namespace mcref
