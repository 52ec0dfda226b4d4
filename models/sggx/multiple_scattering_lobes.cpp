#include "models/sggx/multiple_scattering_lobes.h"

#include <cmath>
#include <stdexcept>

#include "models/sggx/single_scattering.h"

namespace mcref::sggx {

namespace {
void require(bool ok, const std::string& key, double value, const std::string& range) {
  require_parameter(ok, "multiple-scattering lobes", key, value, range);
}
}  // namespace

void check_lobes(const MultipleScatteringLobes& lobes, std::size_t stack_layers) {
  require(lobes.layers.size() == stack_layers, "layers (count)", static_cast<double>(lobes.layers.size()),
          std::to_string(stack_layers) + ", one per layer of the stack");
  require(lobes.w1 >= 0 && std::isfinite(lobes.w1), "w1", lobes.w1, "[0, inf)");
  require(lobes.w2 >= 0 && std::isfinite(lobes.w2), "w2", lobes.w2, "[0, inf)");
  require(lobes.split.reflection >= 0 && std::isfinite(lobes.split.reflection), "split.reflection",
          lobes.split.reflection, "[0, inf)");
  require(lobes.split.transmission >= 0 && std::isfinite(lobes.split.transmission), "split.transmission",
          lobes.split.transmission, "[0, inf)");
  for (std::size_t k = 0; k < lobes.layers.size(); ++k) {
    const ModifiedLayer& m = lobes.layers[k];
    const std::string p = "layers[" + std::to_string(k) + "].";
    require(m.alpha > 0 && std::isfinite(m.alpha), p + "alpha", m.alpha, "(0, inf)");
    require(m.thickness >= 0 && std::isfinite(m.thickness), p + "thickness", m.thickness, "[0, inf)");
    for (int c = 0; c < 3; ++c) {
      require(m.albedo[c] >= 0 && m.albedo[c] <= 1, p + "albedo[" + std::to_string(c) + "]", m.albedo[c], "[0, 1]");
      require(m.f0[c] >= 0 && m.f0[c] <= 1, p + "f0[" + std::to_string(c) + "]", m.f0[c], "[0, 1]");
    }
  }
}

std::vector<FlakeLayer> modified_stack(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes) {
  check_lobes(lobes, original.size());
  std::vector<FlakeLayer> out = original;
  for (std::size_t k = 0; k < out.size(); ++k) {
    check_flake_layer(original[k], "layer " + std::to_string(k));
    out[k].alpha = lobes.layers[k].alpha;
    out[k].thickness = lobes.layers[k].thickness;
    out[k].albedo = lobes.layers[k].albedo;
    out[k].f0 = lobes.layers[k].f0;
  }
  return out;
}

double lambertian_lobe(const LambertianSplit& split, Vec3 wi, Vec3 wo) {
  if (wi.z == 0 || wo.z == 0) return 0;
  return ((wi.z > 0) == (wo.z > 0) ? split.reflection : split.transmission) / kPi;
}

double multiple_scattering_bsdf(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes, int c,
                                Vec3 wi, Vec3 wo) {
  if (c < 0 || c > 2)
    throw std::invalid_argument("multiple-scattering lobes: channel = " + std::to_string(c) +
                                " is out of range (allowed: 0, 1, 2)");
  const std::vector<FlakeLayer> modified = modified_stack(original, lobes);
  return lobes.w1 * single_scattering_bsdf(flake_stack(modified, c), wi, wo) +
         lobes.w2 * lambertian_lobe(lobes.split, wi, wo);
}

Rgb multiple_scattering_bsdf_rgb(const std::vector<FlakeLayer>& original, const MultipleScatteringLobes& lobes,
                                 Vec3 wi, Vec3 wo) {
  return {multiple_scattering_bsdf(original, lobes, 0, wi, wo), multiple_scattering_bsdf(original, lobes, 1, wi, wo),
          multiple_scattering_bsdf(original, lobes, 2, wi, wo)};
}

}  // namespace mcref::sggx
