#pragma once
// The micrograin BSDF models (issue #3), per colour channel, real directions
// i, o (unit, z > 0, pointing away from the surface), values in 1/sr without
// the cosine.
//
// LRPB23 Eq. 1–2:
//   f = w+(i, o) f^S + (1 - w+(i, o)) f^B,   w+ of Eq. 24,
//   f^S = K_d / pi T(i, o) + D(h) G(i, o) F(i.h) / (4 |i.n| |o.n|),
// with the micrograin D (Eq. 17), G = 1 / (1 + Lambda(i) + Lambda(o)) (the
// height-correlated Smith form of Heitz 2014, from G1 = 1/(1 + Lambda) as in
// Sec. 5.2; the text also reads as the separable G1(i) G1(o): SmithG2) with Lambda by the series n = 4 (Eq. 25), by quadrature, or the
// GGX Lambda at alpha~ (Eq. 18). T = 1 for Lambertian grains; for
// diffuse + specular grains T = (1 - F(i.n))(1 - F(o.n)) / (eta^2 (1 - K_d Fbar_int))
// (Mitsuba's plastic, which LRPB23 say their T is inspired by; their exact
// form is in supplemental material we do not have).
//
// vNDF paper Eq. 1 (LRPB24's form): f = tau0 f_S + V_p(i, o) f_B, where
// tau0 f_S is single scattering on the grains with the height-correlated
// masking: tau0 / (|i.n||o.n|) ∫ D(m) f_micro(i, o, m) <i.m><o.m> G(i, o, h(m)) dm,
// with either G(i, o, h) = G_dist(i, h) G_dist(o, h) and
// V_p(i, o) = (1 - tau0) V(i) V(o), V(d) = (1 - tau+(d)) / (1 - tau0) (TwoWay::Product,
// which makes V_p f_B identical to LRPB23's (1 - w+) f^B and assumes masking toward
// i and toward o independent), or the exact Poisson void probabilities over the
// union of the two shadow sets (TwoWay::Union; two_way_masking.h, pore_visibility.h).
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// A micro-BRDF, one colour channel (mirrors sim/micrograin/micro_brdf.h).
struct MicroSurface {
  enum class Type { Black, Lambertian, Conductor, RoughConductor, DiffuseSpecular };
  Type type = Type::Lambertian;
  double kd = 0.8;               // lambertian, diffuse_specular body albedo
  double eta = 1.5, kappa = 0;   // conductors
  double ior = 1.5;              // diffuse_specular interface
  double alpha = 0.3;            // rough_conductor (GGX)
};

enum class LambdaMethod { Series4, Quadrature, GgxEquivalent };

// The two readings of LRPB23 Eq. 2's G "computed (cf. Heitz 2014) from
// G1 = 1/(1 + Lambda)" (issue #15): height-correlated 1/(1 + Lambda(i) + Lambda(o))
// (Heitz 2014 Eq. 99) or separable G1(i) G1(o) (Heitz 2014 Eq. 98; the authors' renderer).
enum class SmithG2 { HeightCorrelated, Separable };

// Smooth-interface Fresnel of a micro-BRDF's mirror lobe at cosine c (0 if it has none).
double specular_fresnel(const MicroSurface& s, double c);

// Non-delta part of a flat micro-BRDF (the base), f(i, o) about n = +z.
double flat_brdf(const MicroSurface& s, Vec3 i, Vec3 o);
// Energy of the mirror (delta) lobe of a flat micro-BRDF for light from cos theta_i.
double flat_delta_energy(const MicroSurface& s, double cos_theta_i);

// Body factor of a diffuse + specular micro-BRDF: K_d / (eta^2 (1 - K_d Fbar_int)).
double body_factor(const MicroSurface& s);

// LRPB23 Eq. 2: f^S (grains).
double lrpb23_surface(const GrainField& f, const MicroSurface& grain, Vec3 i, Vec3 o, LambdaMethod lambda,
                      SmithG2 g2 = SmithG2::HeightCorrelated);
// LRPB23 Eq. 1 without the base's delta lobe: w+ f^S and (1 - w+) f^B.
double lrpb23_grain_part(const GrainField& f, const MicroSurface& grain, Vec3 i, Vec3 o, LambdaMethod lambda,
                         SmithG2 g2 = SmithG2::HeightCorrelated);
double lrpb23_base_part(const GrainField& f, const MicroSurface& base, Vec3 i, Vec3 o);
// Delta energy of LRPB23 Eq. 1 (smooth base): (1 - w+(i, mirror(i))) F_base(cos theta_i).
double lrpb23_base_delta_energy(const GrainField& f, const MicroSurface& base, Vec3 i);

// Two-direction masking of vNDF Eq. 1: the product of the one-way terms
// (G_dist(i, h) G_dist(o, h); base: V(i) V(o), Eq. 24), or the exact union
// form exp(-rho' |K_i U K_o|) (two_way_masking.h, pore_visibility.h; issue #15).
enum class TwoWay { Product, Union };

// vNDF paper Eq. 1, grain term: tau0 f_S, single scattering on grains with
// G_dist(i, h) G_dist(o, h) (see above) or G_dist(i, o, h); the specular part in
// closed form, the diffuse part by quadrature over the unit-space normals.
double gdist_grain_single_scattering(const GrainField& f, const MicroSurface& grain, Vec3 i, Vec3 o,
                                     TwoWay masking = TwoWay::Product);
// Its specular part alone (conductor and diffuse + specular grains; else 0):
// tau0 D(h) G F(i.h) / (4 |i.n||o.n|); gdist_specular_geometry is its
// channel-independent factor tau0 D(h) G.
double gdist_grain_specular(const GrainField& f, const MicroSurface& grain, Vec3 i, Vec3 o,
                            TwoWay masking = TwoWay::Product);
double gdist_specular_geometry(const GrainField& f, Vec3 i, Vec3 o, TwoWay masking = TwoWay::Product);
bool has_specular_lobe(const MicroSurface& grain);
// Its diffuse geometry factor (1/pi) tau0 / (|i.n||o.n|) ∫ D <i.m><o.m> T_i T_o G dm,
// T = 1 - F_dielectric(ior) of the local angle (ior <= 1: T = 1, Lambertian).
// rel_tol: the quadratures' relative tolerance (their error is far below it,
// within 1e-6 at the default: tests/models/test_micrograin_gdist.cpp); the ring
// integral is exact for isotropic grains without Fresnel (clipped_cosines.h).
double gdist_diffuse_geometry(const GrainField& f, Vec3 i, Vec3 o, double ior, TwoWay masking = TwoWay::Product,
                              double rel_tol = 1e-8);

// vNDF paper Eq. 1, base term V_p(i, o) f_B with V_p = P(base point in a pore, seen
// from i and o): (1 - tau0) V(i) V(o) (= lrpb23_base_part) or the union form.
double gdist_base_part(const GrainField& f, const MicroSurface& base, Vec3 i, Vec3 o, TwoWay masking);
// Its delta energy (smooth base): V_p(i, mirror(i)) F_base(cos theta_i).
double gdist_base_delta_energy(const GrainField& f, const MicroSurface& base, Vec3 i, TwoWay masking);

}  // namespace mcref::micrograin
