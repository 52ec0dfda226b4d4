#pragma once
// Tables derived per batch from the BRDF tables of a Lambertian-sphere volume
// (issue #5, d'Eon 2021 Fig. 2 and Sec. 3.5), so that each has its own stderr
// from the batch-to-batch spread:
//
//   <name>_modes  (quantity "brdf_modes", 1/sr): the azimuthal Fourier modes of
//     Eq. 9, f = f^(0) + f^(1) cos(phi) + f^(2) cos(2 phi), i.e.
//     f^(0) = (1/pi) \int_0^pi f dphi, f^(k) = (2/pi) \int_0^pi f cos(k phi) dphi,
//     of the total BRDF; axes theta_i (points), theta_o (the brdf bins,
//     cosine-weighted bin averages as in the brdf table), mode k (points 0, 1, 2),
//     channel. Averaged over phi_i (isotropic samples). From uniform folded phi
//     bins of width D with bin averages f_b:
//       f^(k) = (c_k / pi) sum_b f_b \int_b cos(k phi) dphi / sinc^2(k D / 2),
//     c_0 = 1, c_k = 2: a bin average of cos(k phi) is attenuated by sinc(k D / 2),
//     so without the division the modes would be low by sinc^2 (2.3 % for k = 2
//     with 12 bins). Exact for any f whose modes above 2 N - 3 vanish (N bins):
//     no smoothing error, only aliasing from modes >= 2 N - k.
//   <name>_kd  (quantity "spherical_albedo", 1): k_d = 2 \int_0^1 a(mu) mu dmu of
//     the directional albedo a (total component of <name>_albedo) by
//     Gauss-Legendre in mu = cos(theta_i); written only when the measure's
//     theta_i are the n Gauss-Legendre nodes of [0, 1] in cos(theta_i) (n >= 2,
//     any order, phi_i averaged). Axis: channel.
// Written by simulate_spheres for placement = "volumetric" (folded, isotropic).
#include <vector>

#include "sim/tally/table.h"

namespace mcref {

// Weights w[b] such that f^(k) = sum_b w[b] f_b for uniform bins of [0, pi]
// (std::invalid_argument if the axis is not that).
std::vector<double> fourier_mode_weights(const Axis& phi, int k);

// Empty mode table for a brdf table (axes theta_i, phi_i, theta_o, phi, channel).
Table make_mode_table(const Table& brdf, int max_mode = 2);
// One batch of the mode table from one batch of the brdf table (its values).
std::vector<double> mode_estimate(const Table& brdf, const std::vector<double>& brdf_batch, const Table& modes);

// Gauss-Legendre weights on [0, 1] matching cos(theta_i) (one per theta_i, in
// the list's order), or empty if theta_i are not the n-point nodes (to 1e-9).
std::vector<double> spherical_albedo_weights(const std::vector<double>& theta_i);
// Empty k_d table for an albedo table (axes theta_i, phi_i, component, channel).
Table make_kd_table(const Table& albedo);
// One batch of k_d from one batch of the albedo table (total component).
std::vector<double> kd_estimate(const Table& albedo, const std::vector<double>& albedo_batch,
                                const std::vector<double>& weights);

}  // namespace mcref
