#pragma once
// Exponential for loops the compiler vectorises (the companion of simd_log.h):
// arithmetic only, no branch and no library call, so the same bits on every
// instruction set (compiled without FMA contraction). fdlibm's e_exp.c:
// x = k ln2 + r, |r| <= ln2 / 2, exp(r) = 1 + r + r c / (2 - c) with
// c = r - r^2 P(r^2), its degree-5 minimax P; exp(x) = 2^k exp(r), within an ulp.
#include <algorithm>
#include <cstdint>
#include <cstring>

namespace mcref {

// exp(x) for x <= 0: 0 below -708 (where exp(x) < 3.3e-308 would need a
// subnormal scale), exact 1 at 0. NaN gives NaN.
inline double simd_exp_nonpositive(double x) {
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10,
                   inv_ln2 = 1.44269504088896338700e+00;
  constexpr double P1 = 1.66666666666666019037e-01, P2 = -2.77777777770155933842e-03, P3 = 6.61375632143793436117e-05,
                   P4 = -1.65339022054652515390e-06, P5 = 4.13813679705723846039e-08;
  const double y = std::max(x, -708.0);  // (std::max keeps a NaN x: it returns its first argument)
  // k = round(y / ln2) by the 1.5 2^52 shifter: its low bits hold k as an integer.
  const double shifted = y * inv_ln2 + 0x1.8p52;
  const double k = shifted - 0x1.8p52;
  const double hi = y - k * ln2_hi, lo = k * ln2_lo, r = hi - lo;
  const double t = r * r;
  const double c = r - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
  const double er = 1 - ((lo - (r * c) / (2 - c)) - hi);
  // 2^k from the shifter's bits: (k + 1023) << 52, the shifter's own high bits shifted out.
  std::uint64_t b;
  std::memcpy(&b, &shifted, 8);
  const std::uint64_t sb = (b + 1023) << 52;
  double scale;
  std::memcpy(&scale, &sb, 8);
  return x < -708.0 ? 0.0 : er * scale;
}

}  // namespace mcref
