#include "sim/slab/escape.h"

#include <cmath>

namespace mcref::volume {

double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d) {
  const std::vector<MediumLayer>& layers = medium.layers();
  if (d.z == 0 || (d.z < 0 && medium.has_substrate())) return 0;
  const int step = d.z > 0 ? -1 : 1, end = d.z > 0 ? -1 : static_cast<int>(layers.size());
  const double inv_mu = 1 / std::fabs(d.z);
  double tau = 0;
  for (int k = layer; k != end; k += step) {
    const MediumLayer& l = layers[k];
    const double from = k == layer ? depth : d.z > 0 ? l.bottom : l.top;
    const double path = std::fabs((d.z > 0 ? l.top : l.bottom) - from) * inv_mu;
    if (l.density > 0) tau += l.density * l.phase->sigma(d) * path;
  }
  return std::exp(-tau);
}

}  // namespace mcref::volume
