#pragma once
// An isotropic BRDF table read as a function f(theta_i, theta_o, phi, channel):
// trilinear interpolation of the bin averages placed at their axis points
// (theta_i: the listed incident angles; theta_o, phi: bin centres; an axis of
// the other kind, from a table made in Python, at its points or centres), for
// export to renderers' formats (mcref export-brdf). Angle axes must be in rad
// and increasing.
//   - phi = phi_o - phi_i is folded into [0, pi] (the tables' convention);
//   - outside the outermost points, the nearest value is held (no extrapolation);
//   - directions below the horizon (cos <= 0) give 0.
// Density rule (refused with a one-line ConfigError otherwise), so that the
// interpolation stays within the tables' resolution:
//   theta_i: at least 2 points, the first <= 5 deg, the last >= 75 deg,
//            consecutive gaps <= 15 deg;
//   theta_o: at least 8 bins;  phi: at least 8 bins over [0, pi] (<= 22.5 deg);
//   phi_i: one point and phi over [0, pi] (an isotropic table: an anisotropic
//          one, phi over [0, 2 pi), would be folded and half of it lost);
//   channel: 1 (grey) or 3 (RGB).
#include <string>

#include "sim/tally/table.h"

namespace mcref {

class BrdfInterpolation {
 public:
  // Throws ConfigError naming `file` and the table if it is not a BRDF table or too coarse.
  BrdfInterpolation(const Table& table, const std::string& file);
  // f_r in 1/sr (no cosine) of channel c (0..2; a grey table repeats its channel).
  double operator()(double theta_i, double theta_o, double phi, int c) const;
  int channels() const { return channels_; }

 private:
  std::vector<double> values_, ti_, to_, ph_;
  int channels_ = 1;
};

}  // namespace mcref
