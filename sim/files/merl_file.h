#pragma once
// MERL BRDF files (Matusik, Pfister, Brand, McMillan 2003; the MERL database's
// BRDFRead.cpp): an isotropic BRDF on the half/difference grid of Rusinkiewicz.
//   header   three int32: 90 90 180  (theta_h, theta_d, phi_d)
//   data     3 x 90 x 90 x 180 float64, channel-major (all R, then G, then B),
//            index = phi_d + 180 (theta_d + 90 theta_h)
//   values   stored as f / scale, scale = 1/1500, 1.15/1500, 1.66/1500 (R, G, B):
//            MERL's reader multiplies by the scale to get f_r in 1/sr.
// Grid angles (the inverse of BRDFRead.cpp's index functions, at their lower
// ends): theta_h = (i/90)^2 pi/2, theta_d = j pi/180, phi_d = k pi/180 in [0, pi)
// (reciprocity folds phi_d into [0, pi)).
// Cosine: MERL's values are the BRDF f_r WITHOUT the cosine factor (what
// BRDFRead.cpp returns and renderers multiply by cos theta_i).
#include <array>
#include <string>
#include <vector>

#include "models/core/vec.h"

namespace mcref {

inline constexpr int kMerlThetaH = 90, kMerlThetaD = 90, kMerlPhiD = 180;
inline constexpr std::size_t kMerlCells = std::size_t{kMerlThetaH} * kMerlThetaD * kMerlPhiD;
inline constexpr std::array<double, 3> kMerlScale{1.0 / 1500, 1.15 / 1500, 1.66 / 1500};

// Incident and outgoing directions of grid cell (i, j, k) (phi_h = 0; both
// may lie below the horizon, z < 0, at large theta_h + theta_d).
void merl_directions(int i_theta_h, int j_theta_d, int k_phi_d, Vec3& wi, Vec3& wo);

// Writes f_r (1/sr, no cosine; rgb[c][cell], cell in MERL's order) as a MERL
// file, through a temporary file renamed into place.
void write_merl_file(const std::string& path, const std::array<std::vector<double>, 3>& rgb);

}  // namespace mcref
