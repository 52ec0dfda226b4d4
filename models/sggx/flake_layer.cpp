#include "models/sggx/flake_layer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mcref::sggx {

void require_parameter(bool ok, const std::string& what, const std::string& key, double value,
                       const std::string& range) {
  if (ok) return;
  std::ostringstream s;
  s << what << ": " << key << " = " << value << " is out of range (allowed: " << range << ")";
  throw std::invalid_argument(s.str());
}

void check_flake_layer(const FlakeLayer& l, const std::string& what) {
  require_parameter(l.alpha > 0 && std::isfinite(l.alpha), what, "alpha", l.alpha, "(0, inf)");
  require_parameter(l.thickness >= 0 && std::isfinite(l.thickness), what, "thickness", l.thickness, "[0, inf)");
  require_parameter(l.density >= 0 && std::isfinite(l.density), what, "density", l.density, "[0, inf)");
  for (int c = 0; c < 3; ++c) {
    require_parameter(l.albedo[c] >= 0 && l.albedo[c] <= 1, what, "albedo[" + std::to_string(c) + "]", l.albedo[c], "[0, 1]");
    require_parameter(l.f0[c] >= 0 && l.f0[c] <= 1, what, "f0[" + std::to_string(c) + "]", l.f0[c], "[0, 1]");
  }
  const double n = length(l.orientation);
  require_parameter(n > 0 && std::isfinite(n), what, "|orientation|", n, "(0, inf)");
}

Layer flake_channel_layer(const FlakeLayer& l, int c) {
  const Sggx s = l.type == FlakeType::kFiber ? fiber_like(l.alpha, l.orientation) : surface_like(l.alpha, l.orientation);
  return sggx_layer(l.thickness, l.density, s, l.albedo[c], l.f0[c]);
}

std::vector<Layer> flake_stack(const std::vector<FlakeLayer>& layers, int c) {
  std::vector<Layer> stack;
  for (const FlakeLayer& l : layers) stack.push_back(flake_channel_layer(l, c));
  return stack;
}

}  // namespace mcref::sggx
