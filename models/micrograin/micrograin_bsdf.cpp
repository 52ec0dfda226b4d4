#include "models/micrograin/micrograin_bsdf.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

#include "models/microfacet/fresnel.h"
#include "models/micrograin/checked_gauss_legendre.h"
#include "models/micrograin/diffuse_ring.h"
#include "models/micrograin/ggx.h"
#include "models/micrograin/height_masking.h"
#include "models/micrograin/ndf.h"
#include "models/micrograin/pore_visibility.h"
#include "models/micrograin/smith_lambda.h"
#include "models/micrograin/two_way_masking.h"
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

constexpr int kPolarHalvings = 30;  // bounds the polar refinement (as the former adaptive rule's depth)

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

double lrpb23_surface(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, LambdaMethod method, SmithG2 g2) {
  double value = 0;
  if (g.type == MicroSurface::Type::Lambertian) value += g.kd / kPi;  // T = 1
  if (g.type == MicroSurface::Type::DiffuseSpecular) value += body_term(g, i.z, o.z);
  if (g.type == MicroSurface::Type::Conductor || g.type == MicroSurface::Type::DiffuseSpecular) {
    const Vec3 h = half_vector(i, o);
    const double li = lambda_of(f, i, method), lo = lambda_of(f, o, method);
    const double G = g2 == SmithG2::Separable ? 1 / ((1 + li) * (1 + lo))  // Heitz 2014 Eq. 98
                                              : 1 / (1 + li + lo);         // Heitz 2014 Eq. 99
    value += ndf(f, h) * G * specular_fresnel(g, dot(i, h)) / (4 * i.z * o.z);      // Eq. 2
  }
  return value;
}

double lrpb23_grain_part(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, LambdaMethod method, SmithG2 g2) {
  return layer_weight(f, i, o) * lrpb23_surface(f, g, i, o, method, g2);  // Eq. 1, 24
}

double lrpb23_base_part(const GrainField& f, const MicroSurface& base, Vec3 i, Vec3 o) {
  return (1 - layer_weight(f, i, o)) * flat_brdf(base, i, o);
}

double lrpb23_base_delta_energy(const GrainField& f, const MicroSurface& base, Vec3 i) {
  const Vec3 mirror{-i.x, -i.y, i.z};
  return (1 - layer_weight(f, i, mirror)) * flat_delta_energy(base, i.z);
}

double gdist_base_part(const GrainField& f, const MicroSurface& base, Vec3 i, Vec3 o, TwoWay masking) {
  if (masking == TwoWay::Product) return lrpb23_base_part(f, base, i, o);
  return base_visibility_union(f, i, o) * flat_brdf(base, i, o);  // vNDF Eq. 1
}

double gdist_base_delta_energy(const GrainField& f, const MicroSurface& base, Vec3 i, TwoWay masking) {
  if (masking == TwoWay::Product) return lrpb23_base_delta_energy(f, base, i);
  const Vec3 mirror{-i.x, -i.y, i.z};
  return base_visibility_union(f, i, mirror) * flat_delta_energy(base, i.z);
}

double gdist_diffuse_geometry(const GrainField& f, Vec3 i, Vec3 o, double ior, TwoWay masking, double rel_tol) {
  // The polar integral is split at its kinks and each piece graded toward its
  // ends (theta' = c + w s(t), s = 3t^2 - 2t^3: the ends behave like
  // |theta' - theta'_c|^(3/2), smooth in t), then checked to rel_tol of the sum
  // of the pieces (checked_gauss_legendre.h; issue #15, part 4).
  // The ring integral over the azimuth, 100 times tighter (diffuse_ring.h).
  auto ring_integral = [&](double h, double st) { return diffuse_ring_integral(f, i, o, ior, h, st, 1e-2 * rel_tol); };
  // Unit-space polar angle theta' of the normal: split where the ring of either
  // direction starts to turn away (theta' = pi/2 - theta'_d), which is also where
  // its distant shadow starts (h = sin theta'_d).
  auto polar = [&](double th) {
    const double h = std::cos(th), st = std::sin(th);
    const double g2 = masking == TwoWay::Union ? distant_masking_union(f, i, o, h)
                                               : distant_masking(f, i, h) * distant_masking(f, o, h);
    // D(m) dw_m = D1(h) |M m'| dw_m' (vNDF Eq. 7 with the Jacobian of the
    // unit-space map m = M m' / |M m'|): D1 is constant on the ring.
    return st * unit_ndf(f.tau0, h) * ring_integral(h, st) * g2;
  };
  const double ti = spherical_theta(to_unit_direction(f, i)), to = spherical_theta(to_unit_direction(f, o));
  const double cuts[] = {0.0, kPi / 2 - std::max(ti, to), kPi / 2 - std::min(ti, to), kPi / 2};
  struct Piece {
    double c, w, fine;
  };
  auto theta = [](const Piece& p, double t) { return p.c + p.w * t * t * (3 - 2 * t); };
  auto graded = [&](const Piece& p) { return [&, p](double t) { return polar(theta(p, t)) * 6 * t * (1 - t) * p.w; }; };
  std::vector<Piece> pieces;
  double scale = 0;
  for (int k = 0; k < 3; ++k)
    if (cuts[k + 1] - cuts[k] > 1e-12) {
      Piece p{cuts[k], cuts[k + 1] - cuts[k], 0.0};
      p.fine = gauss_legendre_24(graded(p), 0.0, 1.0);
      scale += std::fabs(p.fine);
      pieces.push_back(p);
    }
  double sum = 0;
  for (const Piece& p : pieces) {
    // The integrand's rounding: h = cos theta' is known to 2^-53, i.e. to
    // ~1e-16 / (1 - h) relative of 1 - h, on which the masking of a grazing
    // direction depends steeply (without this floor a direction within 1e-8
    // of grazing would refine for ever).
    auto rounding = [&](double, double t_hi) {
      const double s = std::sin(0.5 * theta(p, t_hi));
      return 1e-14 + 1e-15 / (2 * s * s);
    };
    sum += checked_gauss_legendre(graded(p), 0.0, 1.0, p.fine, rel_tol * scale / 3, rounding, kPolarHalvings);
  }
  return f.tau0 * sum / (kPi * i.z * o.z);
}

bool has_specular_lobe(const MicroSurface& g) {
  return g.type == MicroSurface::Type::Conductor || g.type == MicroSurface::Type::DiffuseSpecular;
}

double gdist_specular_geometry(const GrainField& f, Vec3 i, Vec3 o, TwoWay masking) {
  const Vec3 h = half_vector(i, o);
  const double height = unit_height(f, h);
  const double G = masking == TwoWay::Union ? distant_masking_union(f, i, o, height)
                                            : distant_masking(f, i, height) * distant_masking(f, o, height);
  return f.tau0 * ndf(f, h) * G;
}

double gdist_grain_specular(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, TwoWay masking) {
  if (!has_specular_lobe(g)) return 0;
  return gdist_specular_geometry(f, i, o, masking) * specular_fresnel(g, dot(i, half_vector(i, o))) / (4 * i.z * o.z);
}

double gdist_grain_single_scattering(const GrainField& f, const MicroSurface& g, Vec3 i, Vec3 o, TwoWay masking) {
  double value = 0;
  if (g.type == MicroSurface::Type::Lambertian) value += g.kd * gdist_diffuse_geometry(f, i, o, 0.0, masking);
  if (g.type == MicroSurface::Type::DiffuseSpecular)
    value += body_factor(g) * gdist_diffuse_geometry(f, i, o, g.ior, masking);
  return value + gdist_grain_specular(f, g, i, o, masking);
}

}  // namespace mcref::micrograin
