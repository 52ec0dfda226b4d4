#include "sim/slab/escape.h"

#include <cmath>
#include <stdexcept>

namespace mcref::volume {

double escape_probability(const SlabMedium& medium, int layer, double depth, Vec3 d) {
  const std::vector<MediumLayer>& layers = medium.layers();
  if (d.z == 0 || (d.z < 0 && medium.has_substrate())) return 0;
  const int step = d.z > 0 ? -1 : 1, end = d.z > 0 ? -1 : static_cast<int>(layers.size());
  const double inv_mu = 1 / std::fabs(d.z);
  const bool grids = medium.grids() != nullptr;
  double tau = 0;
  for (int k = layer; k != end; k += step) {
    const MediumLayer& l = layers[k];
    const double from = k == layer ? depth : d.z > 0 ? l.bottom : l.top;
    if (grids) {
      const std::optional<DepthProfile>& profile = medium.depth_profiles()[k];
      if (!profile) throw std::invalid_argument(escape_unsupported(medium));
      // sigma(d) as the layer's free flights take it (the grids' S).
      if (const double column = profile->column_to_face(from, d.z < 0); column > 0)
        tau += medium.majorants()[k].factor(d) * column * inv_mu;
      continue;
    }
    const double path = std::fabs((d.z > 0 ? l.top : l.bottom) - from) * inv_mu;
    if (l.density > 0) tau += l.density * l.phase->sigma(d) * path;
  }
  return std::exp(-tau);
}

std::string escape_unsupported(const SlabMedium& medium) {
  if (!medium.grids()) return "";
  for (std::size_t k = 0; k < medium.depth_profiles().size(); ++k)
    if (!medium.depth_profiles()[k])
      return "the next-event estimators need every OpenVDB layer to vary in depth only, with one SGGX matrix; layer " +
             std::to_string(k) + " varies laterally or in S (or was built without depth profiles)";
  return "";
}

}  // namespace mcref::volume
