#pragma once
#include <functional>
// Mapping between the particle albedo c and the spherical (bond) albedo k_d of
// the material (d'Eon 2021, Sec. 3.5): k_d = (1/pi) \int\int f_r cos_i cos_o dw_i dw_o.

namespace mcref::lambert_sphere {

// Eq. 39: c = (1 - 1.00425 (1 - k_d)^2.67103) / (1 - 0.219924 (1 - k_d)^2.44559).
double albedo_from_kd(double kd);
// Eq. 40: k_d = (-0.453029 (1 - c) - 0.544162 sqrt(1 - c) + 1) / (1.42931 sqrt(1 - c) + 1).
double kd_from_albedo(double c);

// max over x in [0, 1] (grid of n + 1 points) of |Eq. 39(Eq. 40(c)) - c| and
// |Eq. 40(Eq. 39(k_d)) - k_d|: how far the two fits are from being inverses.
struct RoundTripError {
  double c_to_kd_to_c = 0, at_c = 0;
  double kd_to_c_to_kd = 0, at_kd = 0;
};
RoundTripError albedo_mapping_round_trip_error(int n = 100000);

// k_d = 4 pi \int_0^1 \int_0^1 f^(0)(mu_i, mu_o) mu_i mu_o dmu_i dmu_o, for a BRDF
// given by its azimuthal mean f^(0) (only that mode carries energy). Tensor
// Gauss-Legendre on panels graded toward 0 ([2^-(j+1), 2^-j], j < 12, 8 points
// each), since f^(0) ~ 1/(mu_i + mu_o) at the corner: 1e-9 relative (tests).
double spherical_albedo(const std::function<double(double, double)>& zeroth_mode);

// k_d of ReferenceBrdf (exact single scattering + exact three-term multiple
// scattering), i.e. what Eq. 40 should return if it maps c to the model's
// spherical albedo. c in [0, 1). ~1 s.
double spherical_albedo_reference(double c);

}  // namespace mcref::lambert_sphere
