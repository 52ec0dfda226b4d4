#include "models/micrograin/micrograin_bsdf.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/microfacet/fresnel.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/height_masking.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/smith_lambda.h"
#include "models/micrograin/unit_space.h"
#include "models/micrograin/visible_filling_factor.h"

namespace mcref::micrograin {

namespace {

// Internal hemispherical Fresnel average of a body of index ior, cached per thread.
double internal_average(double ior) {
  thread_local double last_ior = -1, last = 0;
  if (ior != last_ior) {
    last = fresnel_dielectric_average(1.0 / ior);
    last_ior = ior;
  }
  return last;
}

Vec3 half_vector(Vec3 i, Vec3 o) { return normalize(i + o); }

double lambda_of(const GrainField& f, Vec3 d, LambdaMethod method) {
  const double theta = spherical_theta(d);
  switch (method) {
    case LambdaMethod::Series4: return lambda_series(f, theta, 4);
    case LambdaMethod::Quadrature: return lambda_quadrature(f, d);
    case LambdaMethod::GgxEquivalent: return lambda_ggx_equivalent(f, theta);
  }
  return 0;
}

// Mitsuba-plastic body term: K_d (1 - F_i)(1 - F_o) / (eta^2 pi (1 - K_d Fbar_int)).
double body_term(const MicroSurface& s, double ci, double co) {
  const double fi = fresnel_dielectric(ci, s.ior), fo = fresnel_dielectric(co, s.ior);
  return s.kd * (1 - fi) * (1 - fo) / (s.ior * s.ior * kPi * (1 - s.kd * internal_average(s.ior)));
}

}  // namespace

double body_factor(const MicroSurface& s) { return s.kd / (s.ior * s.ior * (1 - s.kd * internal_average(s.ior))); }

double specular_fresnel(const MicroSurface& s, double c) {
  switch (s.type) {
    case MicroSurface::Type::Conductor:
    case MicroSurface::Type::RoughConductor: return fresnel_conductor(c, s.eta, s.kappa);
    case MicroSurface::Type::DiffuseSpecular: return fresnel_dielectric(c, s.ior);
    default: return 0;
  }
}

double flat_brdf(const MicroSurface& s, Vec3 i, Vec3 o) {
  if (i.z <= 0 || o.z <= 0) return 0;
  switch (s.type) {
    case MicroSurface::Type::Lambertian: return s.kd / kPi;
    case MicroSurface::Type::DiffuseSpecular: return body_term(s, i.z, o.z);
    case MicroSurface::Type::RoughConductor: {
      const Vec3 h = half_vector(i, o);
      const double g2 = 1 / (1 + ggx_lambda(s.alpha, spherical_theta(i)) + ggx_lambda(s.alpha, spherical_theta(o)));
      return ggx_ndf(s.alpha, spherical_theta(h)) * g2 * specular_fresnel(s, dot(i, h)) / (4 * i.z * o.z);
    }
    default: return 0;
  }
}

double flat_delta_energy(const MicroSurface& s, double c) {
  return s.type == MicroSurface::Type::Conductor || s.type == MicroSurface::Type::DiffuseSpecular ? specular_fresnel(s, c)
                                                                                                   : 0.0;
}

double lrpb23_surface(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, LambdaMethod method) {
  double value = 0;
  if (g.type == MicroSurface::Type::Lambertian) value += g.kd / kPi;  // T = 1
  if (g.type == MicroSurface::Type::DiffuseSpecular) value += body_term(g, i.z, o.z);
  if (g.type == MicroSurface::Type::Conductor || g.type == MicroSurface::Type::DiffuseSpecular) {
    const Vec3 h = half_vector(i, o);
    const double G = 1 / (1 + lambda_of(f, i, method) + lambda_of(f, o, method));  // Heitz 2014 Eq. 99
    value += ndf(f, h) * G * specular_fresnel(g, dot(i, h)) / (4 * i.z * o.z);      // Eq. 2
  }
  return value;
}

double lrpb23_grain_part(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, LambdaMethod method) {
  return layer_weight(f, i, o) * lrpb23_surface(f, g, i, o, method);  // Eq. 1, 24
}

double lrpb23_base_part(const GrainField& f, const MicroSurface& base, Vec3 i, Vec3 o) {
  return (1 - layer_weight(f, i, o)) * flat_brdf(base, i, o);
}

double lrpb23_base_delta_energy(const GrainField& f, const MicroSurface& base, Vec3 i) {
  const Vec3 mirror{-i.x, -i.y, i.z};
  return (1 - layer_weight(f, i, mirror)) * flat_delta_energy(base, i.z);
}

double gdist_diffuse_geometry(const GrainField& f, Vec3 i, Vec3 o, double ior) {
  // Unit-space polar angle of the normal: theta'; split where the shadows of
  // i and o start (h = sin theta_d', i.e. theta' = pi/2 - theta_d').
  const double ti = spherical_theta(to_unit_direction(f, i)), to = spherical_theta(to_unit_direction(f, o));
  std::vector<double> cuts{0.0, kPi / 2 - std::max(ti, to), kPi / 2 - std::min(ti, to), kPi / 2};
  static const GaussLegendre rule(16);
  constexpr int nphi = 128;
  // cos and sin of the ring's azimuths 2 pi (p + 1/2) / nphi.
  static const std::vector<Vec3> ring_azimuths = [] {
    std::vector<Vec3> v(nphi);
    for (int p = 0; p < nphi; ++p) v[p] = {std::cos(2 * kPi * (p + 0.5) / nphi), std::sin(2 * kPi * (p + 0.5) / nphi), 0};
    return v;
  }();
  const bool fresnel = ior > 1;
  double sum = 0;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    const double a = cuts[c], b = cuts[c + 1];
    if (b - a <= 1e-12) continue;
    for (std::size_t k = 0; k < rule.x.size(); ++k) {
      const double th = 0.5 * (a + b) + 0.5 * (b - a) * rule.x[k];
      const double h = std::cos(th), st = std::sin(th);
      const double gi = distant_masking(f, i, h), go = distant_masking(f, o, h);
      // D(m) dw_m = D1(h) |M m'| dw_m' (vNDF Eq. 7 with the Jacobian of the
      // unit-space map m = M m' / |M m'|): D1 is constant on the ring.
      const double d1 = unit_ndf(f.tau0, h);
      double ring = 0;
      for (const Vec3& az : ring_azimuths) {
        const Vec3 mm{st * az.x * f.beta_x, st * az.y * f.beta_y, h};  // M m'
        const double len = std::sqrt(dot(mm, mm));
        const Vec3 m = mm * (1 / len);
        const double im = dot(i, m), om = dot(o, m);
        if (im <= 0 || om <= 0) continue;
        double t = 1;
        if (fresnel) t = (1 - fresnel_dielectric(im, ior)) * (1 - fresnel_dielectric(om, ior));
        ring += len * im * om * t;
      }
      sum += 0.5 * (b - a) * rule.w[k] * st * d1 * ring * (2 * kPi / nphi) * gi * go;
    }
  }
  const double tau0 = f.tau0;
  return tau0 * sum / (kPi * i.z * o.z);
}

double gdist_grain_single_scattering(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o) {
  double value = 0;
  if (g.type == MicroSurface::Type::Lambertian) value += g.kd * gdist_diffuse_geometry(f, i, o, 0.0);
  if (g.type == MicroSurface::Type::DiffuseSpecular)
    value += body_factor(g) * gdist_diffuse_geometry(f, i, o, g.ior);
  if (g.type == MicroSurface::Type::Conductor || g.type == MicroSurface::Type::DiffuseSpecular) {
    const Vec3 h = half_vector(i, o);
    const double height = unit_height(f, h);
    const double G = distant_masking(f, i, height) * distant_masking(f, o, height);
    value += f.tau0 * ndf(f, h) * G * specular_fresnel(g, dot(i, h)) / (4 * i.z * o.z);
  }
  return value;
}

}  // namespace mcref::micrograin
