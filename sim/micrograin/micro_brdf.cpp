#include "sim/micrograin/micro_brdf.h"

#include <algorithm>
#include <cmath>

#include "models/core/frame.h"
#include "models/core/warp.h"
#include "models/microfacet/fresnel.h"
#include "models/microfacet/ggx.h"

namespace mcref {

namespace mg = micrograin;

std::string MicroBrdf::name() const {
  switch (type) {
    case Type::Black: return "black";
    case Type::Lambertian: return "lambertian";
    case Type::Conductor: return "conductor";
    case Type::RoughConductor: return "rough_conductor";
    case Type::DiffuseSpecular: return "diffuse_specular";
  }
  return "?";
}

namespace {

Vec3 mirror(Vec3 w, Vec3 n) { return n * (2 * dot(w, n)) - w; }

// The Lambertian body under a smooth dielectric: the light refracted into the
// body bounces (albedo K_d, cosine-distributed) between body and interface
// until it leaves (local frame, n = +z). Returns the exit direction, or z <= 0
// if the path was cut (never in practice: see the bound).
MicroBrdfSample diffuse_under_dielectric(const MicroBrdf& b, Rng& rng) {
  MicroBrdfSample s;
  s.weight = Rgb(1.0);
  for (int bounce = 0; bounce < 100000; ++bounce) {
    s.weight = s.weight * b.albedo;
    // Russian roulette on the body albedo keeps the loop short for bright bodies.
    const double q = std::min(1.0, s.weight.max());
    if (q <= 0 || rng.uniform() >= q) {
      s.absorbed = true;
      return s;
    }
    s.weight = s.weight / q;
    const Vec3 w = sample_cosine_hemisphere(rng);  // inside, toward the interface
    const double f_in = mg::fresnel_dielectric(w.z, 1.0 / b.ior);        // from the body side
    if (rng.uniform() < f_in) continue;                                     // reflected back to the body
    const double sin2_out = b.ior * b.ior * (1 - w.z * w.z);
    const double scale = b.ior;  // tangential components scale by eta
    s.wo = normalize(Vec3{w.x * scale, w.y * scale, std::sqrt(std::fmax(0.0, 1 - sin2_out))});
    return s;
  }
  s.absorbed = true;
  return s;
}

}  // namespace

MicroBrdfSample sample_micro_brdf(const MicroBrdf& b, Vec3 wi, Vec3 n, Rng& rng) {
  MicroBrdfSample s;
  if (b.type == MicroBrdf::Type::Lambertian) {  // ignores wi
    s.wo = sample_cosine_about(n, rng);  // unnormalised: no frame, no division
    s.weight = b.albedo;
    return s;
  }
  wi = normalize(wi);
  const double c = std::clamp(dot(wi, n), 0.0, 1.0);
  switch (b.type) {
    case MicroBrdf::Type::Black:
      s.absorbed = true;
      return s;
    case MicroBrdf::Type::Lambertian:
      break;  // (above)
    case MicroBrdf::Type::Conductor:
      s.wo = mirror(wi, n);
      s.weight = fresnel_conductor(c, b.eta, b.kappa);
      s.delta = true;
      return s;
    case MicroBrdf::Type::RoughConductor: {
      const Frame fr(n);
      const Vec3 wl = fr.to_local(wi);
      const Vec3 m = sample_ggx_visible_normal(b.alpha, wl, rng.uniform(), rng.uniform());
      const Vec3 ol = mirror(wl, m);
      if (ol.z <= 0) {
        s.absorbed = true;
        return s;
      }
      const double li = ggx_lambda(b.alpha, wl), lo = ggx_lambda(b.alpha, ol);
      s.wo = fr.to_world(ol);
      s.weight = fresnel_conductor(dot(wl, m), b.eta, b.kappa) * ((1 + li) / (1 + li + lo));
      return s;
    }
    case MicroBrdf::Type::DiffuseSpecular: {
      if (rng.uniform() < mg::fresnel_dielectric(c, b.ior)) {
        s.wo = mirror(wi, n);
        s.weight = Rgb(1.0);
        s.delta = true;
        return s;
      }
      s = diffuse_under_dielectric(b, rng);
      if (!s.absorbed) s.wo = Frame(n).to_world(s.wo);
      return s;
    }
  }
  s.absorbed = true;
  return s;
}

Rgb micro_brdf_albedo(const MicroBrdf& b, double cos_theta_i, Rng& rng, int samples) {
  const double st = std::sqrt(std::fmax(0.0, 1 - cos_theta_i * cos_theta_i));
  const Vec3 wi{st, 0, cos_theta_i}, n{0, 0, 1};
  switch (b.type) {
    case MicroBrdf::Type::Black: return Rgb(0.0);
    case MicroBrdf::Type::Lambertian: return b.albedo;
    case MicroBrdf::Type::Conductor: return fresnel_conductor(cos_theta_i, b.eta, b.kappa);
    default: break;
  }
  Rgb sum;
  for (int k = 0; k < samples; ++k) {
    const MicroBrdfSample s = sample_micro_brdf(b, wi, n, rng);
    if (!s.absorbed) sum = sum + s.weight;
  }
  return sum / samples;
}

}  // namespace mcref
