#pragma once
// Smith Lambda of the micrograin NDF (LRPB23 Sec. 5.2, Eq. 25), G1 = 1/(1 + Lambda),
// computed three ways:
//  (a) the series of Eq. 25. With pi gamma = -ln(1 - tau0), mu = cot theta,
//      R = sqrt(beta^2 + mu^2) (papers/README.md):
//        Lambda = (F0 + F1 + ...) / (e^{pi gamma} - 1),
//      F_k = (pi gamma)^{k+1} / k! * I_k,
//      I_k = (1/cos theta) ∫ <w.m>^- (1 - s)^k D_GGX(m; beta) dm,
//      s = tan^2 theta_m / (beta^2 + tan^2 theta_m) (so 1 - s = cos^2 of the
//      unit-space angle); this follows from expanding (1 - tau0)^s =
//      e^{-pi gamma} e^{pi gamma (1 - s)} in Eq. 17. Closed forms for k <= 4
//      (README) and their pattern for any k (F_k = (pi gamma)^{k+1} / (2 (k+1)!) *
//      (S_k(x) / (1 + x)^{k - 1/2} - 1), x = beta^2 / mu^2, S_k the binomial
//      series of (1 + x)^{k - 1/2} cut after x^k; issue #15), quadrature for any k;
//  (b) quadrature of the Smith integral 1 + Lambda = ∫ <w.m>^+ D(m) dm / cos theta
//      with the exact D of Eq. 17, evaluated as Lambda = ∫ <w.m>^- D dm / cos theta
//      (equal because ∫ (w.m) D dm = cos theta for a normalised, azimuthally
//      symmetric D). The azimuthal integral is done in closed form,
//      ∫ <a cos phi + b>^- dphi = 2 (a sin phi0 - b (pi - phi0)), cos phi0 = -b/a,
//      and the polar one by Gauss–Legendre in the unit-space angle
//      theta' (tan theta_m = beta tan theta'), graded quadratically at the
//      kink theta_m = pi/2 - theta; accurate to ~1e-10 relative up to 89°;
//  (c) the GGX Lambda at the equivalent roughness alpha~ (Eq. 18).
//
// Isotropic: these use f.beta_x (require beta_x == beta_y), except the Vec3
// overload of lambda_quadrature. Ranges: tau0 in (0, 1), beta > 0,
// theta in [0, pi/2) (Lambda(0) = 0); k, n >= 0.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// F_k in closed form for any k >= 0 (papers/README.md gives k = 0..4).
double lambda_series_term(double tau0, double beta, double theta, int k);

// F_k by quadrature of its defining integral, any k >= 0.
double lambda_series_term_quadrature(double tau0, double beta, double theta, int k);

// (a) Eq. 25 truncated after F_n (n + 1 terms), closed-form terms.
double lambda_series(const GrainField& f, double theta, int n);

// (b) Smith integral with the exact NDF (isotropic, beta = f.beta_x).
double lambda_quadrature(const GrainField& f, double theta);

// (b) for any field and real direction d (d.z > 0): Lambda is invariant under
// the unit-space map, so this is the beta = 1 quadrature at the unit-space angle.
double lambda_quadrature(const GrainField& f, Vec3 d);

// (c) GGX Lambda at alpha~ = equivalent_roughness(tau0, beta) (Eq. 18).
double lambda_ggx_equivalent(const GrainField& f, double theta);

}  // namespace mcref::micrograin
