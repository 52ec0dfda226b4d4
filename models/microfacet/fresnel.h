#pragma once
// Exact Fresnel reflectance of smooth interfaces, unpolarised light, used by
// the grain and base micro-BRDFs of micrograin transport (issue #3) and by
// the micrograin BSDF models (LRPB23 Eq. 2's F).
//
// Ranges: cos_theta in [0, 1] (clamped), the cosine of the angle between the
// incident direction and the normal on the incident side; eta > 0 the ratio
// n_transmitted / n_incident (eta < 1 gives total internal reflection);
// kappa >= 0 the extinction coefficient of a conductor.
#include <complex>

namespace mcref::micrograin {

// Dielectric interface, real eta: (R_s + R_p) / 2, 1 under total internal reflection.
double fresnel_dielectric(double cos_theta, double eta);

// Conductor, complex index eta + i kappa: (|r_s|^2 + |r_p|^2) / 2, with the
// complex cos theta_t = sqrt(1 - sin^2 theta / (eta + i kappa)^2).
double fresnel_conductor(double cos_theta, double eta, double kappa);

// Hemispherical average 2 ∫ F(mu) mu dmu of the dielectric Fresnel (eta may be < 1:
// the internal reflectance of a body of index 1/eta), by Gauss–Legendre.
double fresnel_dielectric_average(double eta);

// Complex indices per RGB channel of the vNDF paper (Fig. 7/9 captions; gold)
// and the usual copper values (Mitsuba's "Cu" at RGB wavelengths), for configs.
struct ComplexIorRgb {
  double eta[3];
  double kappa[3];
};
inline constexpr ComplexIorRgb kGold{{0.18299, 0.42108, 1.37340}, {3.42420, 2.34590, 1.77040}};
inline constexpr ComplexIorRgb kCopper{{0.27105, 0.67693, 1.31640}, {3.60920, 2.62480, 2.29210}};

}  // namespace mcref::micrograin
