#pragma once
// Natural logarithm for loops the compiler vectorises: integer and
// floating-point arithmetic only, no branch and no library call, so the same
// bits on every instruction set (compiled without FMA contraction). fdlibm's
// e_log.c: x = 2^k (1 + f) with 1 + f in [sqrt(2)/2, sqrt(2)), s = f / (2 + f),
// log(1 + f) = f - s (f - R(s^2)) with its degree-14 minimax R (error < 1 ulp
// of R); the result is within a few ulp of log(x).
#include <cstdint>
#include <cstring>

namespace mcref {

// log(x) for positive, normal, finite x (no check).
inline double simd_log(double x) {
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
  constexpr double Lg1 = 6.666666666666735130e-01, Lg2 = 3.999999999940941908e-01, Lg3 = 2.857142874366239149e-01,
                   Lg4 = 2.222219843214978396e-01, Lg5 = 1.818357216161805012e-01, Lg6 = 1.531383769920937332e-01,
                   Lg7 = 1.479819860511658591e-01;
  std::uint64_t b;
  std::memcpy(&b, &x, 8);
  // The mantissa 1 + f in [1, 2), halved when above sqrt(2) (mantissa bits 0x6a09e667f3bcd).
  const std::uint64_t mant = b & 0x000fffffffffffffULL;
  const std::uint64_t big = static_cast<std::int64_t>(mant) > 0x6a09e667f3bcdLL ? 1 : 0;  // (signed: AVX2 compares)
  const std::uint64_t mb = mant | ((0x3ffULL - big) << 52);
  double m;
  std::memcpy(&m, &mb, 8);
  // k = exponent + big as a double without an int64 conversion: 2^52 + e - 2^52.
  const std::uint64_t eb = 0x4330000000000000ULL | ((b >> 52) + big);
  double dk;
  std::memcpy(&dk, &eb, 8);
  dk = dk - 0x1p52 - 1023;
  const double f = m - 1, s = f / (2 + f), z = s * s, w = z * z;
  const double t1 = w * (Lg2 + w * (Lg4 + w * Lg6)), t2 = z * (Lg1 + w * (Lg3 + w * (Lg5 + w * Lg7)));
  const double R = t2 + t1;
  return dk * ln2_hi - ((s * (f - R) - dk * ln2_lo) - f);
}

}  // namespace mcref
