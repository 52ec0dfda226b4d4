#pragma once
// SpongeCake single scattering (Wang, Jin, Hasan, Yan 2022, Eq. 8-16, Sec. 4.4-4.5)
// for a stack of homogeneous layers without interfaces.
//
// Conventions (mcref):
// - z is the macro normal; directions point AWAY from the surface: wi toward
//   the light, wo toward the receiver. Reflection: wi, wo on the same side of
//   the stack; transmission: on opposite sides. Light may arrive from either side.
// - Returned f_r, f_t are BSDF values in 1/sr WITHOUT the cosine factor.
// - Here every "cos" is |cos| = |w.z| and Lambda(w) = sigma(w)/|w.z| >= 0.
//   The paper's Eq. 16 uses the SIGNED Lambda (negative below the horizon);
//   transmission_G_eq16_as_printed() keeps that form for comparison.
// - The stack is listed from the top (the +z face) downward; an optional
//   substrate lies under the last layer.
// - "Single scattering" = exactly one interaction: one volume scattering event
//   (reflection/transmission lobes), or one substrate bounce (substrate term).
#include <vector>

#include "models/sggx/layer.h"

namespace mcref::sggx {

// G of Eq. 12 (reflection), tau = T rho, lambdas >= 0:
//   (1 - exp(-tau (Li + Lo))) / (Li + Lo);  tau = inf gives 1/(Li + Lo).
double reflection_G(double tau, double lambda_i, double lambda_o);
// G of Eq. 16 (transmission) with lambdas >= 0 (|cos|):
//   (exp(-tau Lo) - exp(-tau Li)) / (Li - Lo), limit tau exp(-tau L) at Li = Lo.
double transmission_G(double tau, double lambda_i, double lambda_o);
// Eq. 16 exactly as printed, with signed lambda_o_signed = sigma(wo)/cos(wo) < 0:
//   (1 - exp(-tau (Li + Lo))) / (Li + Lo) * exp(tau Lo). NaN (0/0) at Li + Lo = 0.
double transmission_G_eq16_as_printed(double tau, double lambda_i, double lambda_o_signed);

// Per-layer single-scattering lobes (index = stack index), each already
// attenuated by the layers crossed before and after it (Sec. 4.4). Reflection
// when wi, wo are on the same side, transmission otherwise; zeros at grazing.
std::vector<double> single_scattering_lobes(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo);
// Sum of the lobes when wi, wo are on the same side (Eq. 11-12); 0 otherwise.
double single_scattering_reflection(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo);
// Sum of the lobes when wi, wo are on opposite sides (Eq. 15-16); 0 otherwise.
double single_scattering_transmission(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo);
// Either of the two, by the sides of wi and wo.
double single_scattering_bsdf(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo);

// Unscattered transmittance exp(-sum_k T_k rho_k sigma_k(w) / |w.z|) (Sec. 4.5).
// The delta BTDF is delta_transmittance(wi) * delta(wo + wi) / |wo.z|.
double delta_transmittance(const std::vector<Layer>& stack, Vec3 w);
// Substrate seen through the stack (Sec. 4.5): f_sub * T(wi) * T(wo) for wi, wo
// both above (z > 0); 0 otherwise. substrate_bsdf = f_sub(wi, wo) without cosine.
double substrate_term(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo, double substrate_bsdf);
// Lambertian substrate of albedo a: substrate_term with f_sub = a / pi.
double lambertian_substrate_term(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo, double albedo);

}  // namespace mcref::sggx
