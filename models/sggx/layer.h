#pragma once
// One homogeneous SpongeCake layer (Wang et al. 2022 Sec. 3): thickness T,
// flake density rho (optical thickness T rho), and a phase function that is
// either a specular SGGX microflake phase (extinction rho sigma(w)) or an
// isotropic / Henyey-Greenstein phase (sigma(w) = 1, extinction rho).
// One colour channel: albedo and f0 are scalars.
//
// Direction convention (phase_sample.h): wi toward the light, wo toward the
// receiver, both pointing away from the scattering point.
#include "models/sggx/phase_sample.h"
#include "models/sggx/sggx_distribution.h"

namespace mcref::sggx {

enum class PhaseKind { kSggxSpecular, kHenyeyGreenstein, kIsotropic };

struct Layer {
  double thickness = 1;   // T (may be +infinity for a half-space)
  double density = 1;     // rho; extinction along w is rho * sigma(w)
  PhaseKind kind = PhaseKind::kIsotropic;
  Sggx sggx = surface_like(1, {0, 0, 1});  // used when kind == kSggxSpecular
  double hg_g = 0;        // used when kind == kHenyeyGreenstein
  double albedo = 1;      // gamma: flake albedo (F = gamma Schlick(f0, |wi.h|)) or
                          // single-scattering albedo of the HG/isotropic medium
  double f0 = 1;          // Schlick normal reflectance of the flakes (SGGX only)

  // Optical thickness T rho.
  double optical_thickness() const;
  // Projected area sigma(w) (Eq. 3, 7); 1 for HG/isotropic.
  double sigma(Vec3 w) const;
  // Extinction coefficient rho sigma(w).
  double extinction(Vec3 w) const { return density * sigma(w); }
  // Normalised phase function f_p(wi -> wo) (no albedo / reflectance).
  double phase(Vec3 wi, Vec3 wo) const;
  // Reduced phase function per unit density (Eq. 5 divided by rho):
  //   sigma(wi) F(h) f_p(wi -> wo) = F(h) D(h) / 4          (SGGX flakes)
  //   albedo * p(wi -> wo)                                  (HG, isotropic)
  // Symmetric in (wi, wo) (Eq. 6).
  double reduced_phase(Vec3 wi, Vec3 wo) const;
  // Samples wo ~ f_p(wi -> .); weight = F(h) or albedo.
  PhaseSample sample_phase(Vec3 wi, double u1, double u2) const;
};

// Factories; throw std::invalid_argument on T < 0, rho < 0, |g| >= 1.
Layer sggx_layer(double thickness, double density, const Sggx& s, double gamma, double f0);
Layer hg_layer(double thickness, double density, double g, double albedo);
Layer isotropic_layer(double thickness, double density, double albedo);

}  // namespace mcref::sggx
