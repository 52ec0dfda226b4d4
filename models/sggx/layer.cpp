#include "models/sggx/layer.h"

#include <cmath>
#include <stdexcept>

#include "models/sggx/flake_phase.h"
#include "models/sggx/hg_phase.h"

namespace mcref::sggx {

double Layer::optical_thickness() const {
  return density == 0 ? 0.0 : thickness * density;  // 0 * inf = 0: an empty half-space
}

double Layer::sigma(Vec3 w) const {
  return kind == PhaseKind::kSggxSpecular ? projected_area(sggx, w) : 1.0;
}

double Layer::phase(Vec3 wi, Vec3 wo) const {
  switch (kind) {
    case PhaseKind::kSggxSpecular: return specular_flake_phase(sggx, wi, wo);
    case PhaseKind::kHenyeyGreenstein: return hg_phase(hg_g, wi, wo);
    case PhaseKind::kIsotropic: break;
  }
  return isotropic_phase();
}

double Layer::reduced_phase(Vec3 wi, Vec3 wo) const {
  if (kind == PhaseKind::kSggxSpecular) {
    // sigma(wi) F D / (4 sigma(wi)) = F D / 4: no division by sigma needed.
    const Vec3 sum = wi + wo;
    const double n2 = dot(sum, sum);
    if (!(n2 > 1e-24)) return 0;
    const Vec3 h = sum / std::sqrt(n2);
    return flake_reflectance(albedo, f0, wi, h) * ndf(sggx, h) / 4;
  }
  return albedo * phase(wi, wo);
}

PhaseSample Layer::sample_phase(Vec3 wi, double u1, double u2) const {
  switch (kind) {
    case PhaseKind::kSggxSpecular: return sample_specular_flake_phase(sggx, albedo, f0, wi, u1, u2);
    case PhaseKind::kHenyeyGreenstein: return sample_hg_phase(hg_g, albedo, wi, u1, u2);
    case PhaseKind::kIsotropic: break;
  }
  return sample_isotropic_phase(albedo, u1, u2);
}

namespace {
void check_slab(double thickness, double density) {
  if (!(thickness >= 0)) throw std::invalid_argument("layer thickness must be >= 0");
  if (!(density >= 0) || !std::isfinite(density)) throw std::invalid_argument("layer density must be finite and >= 0");
}
}  // namespace

Layer sggx_layer(double thickness, double density, const Sggx& s, double gamma, double f0) {
  check_slab(thickness, density);
  Layer l;
  l.thickness = thickness;
  l.density = density;
  l.kind = PhaseKind::kSggxSpecular;
  l.sggx = s;
  l.albedo = gamma;
  l.f0 = f0;
  return l;
}

Layer hg_layer(double thickness, double density, double g, double albedo) {
  check_slab(thickness, density);
  if (!(std::fabs(g) < 1)) throw std::invalid_argument("HG asymmetry g must satisfy |g| < 1");
  Layer l;
  l.thickness = thickness;
  l.density = density;
  l.kind = PhaseKind::kHenyeyGreenstein;
  l.hg_g = g;
  l.albedo = albedo;
  return l;
}

Layer isotropic_layer(double thickness, double density, double albedo) {
  check_slab(thickness, density);
  Layer l;
  l.thickness = thickness;
  l.density = density;
  l.kind = PhaseKind::kIsotropic;
  l.albedo = albedo;
  return l;
}

}  // namespace mcref::sggx
