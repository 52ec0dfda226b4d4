#pragma once
// Test helper: the zeros of a sinusoid A + B cos a + C sin a in [0, 2 pi), found
// independently of clipped_cosines.h by the half-angle substitution t = tan(a / 2):
// (A - B) t^2 + 2 C t + (A + B) = 0, roots by the cancellation-free quadratic formula.
#include <cmath>
#include <vector>

#include "models/core/vec.h"
#include "models/micrograin/clipped_cosines.h"

namespace mcref::micrograin {

inline void add_half_angle_zeros(const Sinusoid& s, std::vector<double>& cuts) {
  const double a2 = s.A - s.B, b2 = 2 * s.C, c2 = s.A + s.B, disc = b2 * b2 - 4 * a2 * c2;
  if (!(disc > 0) || a2 == 0) return;
  const double r = -0.5 * (b2 + std::copysign(std::sqrt(disc), b2));
  for (double t : {r / a2, c2 / r}) cuts.push_back(std::fmod(2 * std::atan(t) + 2 * kPi, 2 * kPi));
}

}  // namespace mcref::micrograin
