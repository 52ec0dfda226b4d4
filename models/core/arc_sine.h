#pragma once
// asin by its Taylor series on [0, 1/2], without a library call:
// asin(s) for |s| <= 1/2, pi/2 - 2 asin(sqrt((1 - |s|)/2)) above, odd in s.
// 22 terms (to s^43): the truncation error is below 1e-16, the rounding error
// a few ulp of pi/2 (tested against std::asin). About half the latency of
// glibc's asin and acos here.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "models/core/polynomial.h"
#include "models/core/vec.h"

namespace mcref {

namespace detail {
// asin(s) = s sum_n c_n s^(2n), c_n = (2n)! / (4^n (n!)^2 (2n + 1)).
template <std::size_t N>
constexpr std::array<double, N> asin_series_coefficients() {
  std::array<double, N> c{};
  double binomial = 1;  // (2n)! / (4^n (n!)^2)
  for (std::size_t n = 0; n < N; ++n) {
    if (n > 0) binomial *= (2.0 * n - 1) / (2.0 * n);
    c[n] = binomial / (2.0 * n + 1);
  }
  return c;
}
inline constexpr std::array<double, 22> kAsin = asin_series_coefficients<22>();

}  // namespace detail

// asin(x) for x in [-1, 1] (clamped outside). No branch: both arguments'
// roots are taken, s = min(y, sqrt((1 - y)/2)) picks the one in [0, 1/2].
inline double asin_series(double x) {
  const double y = std::min(std::fabs(x), 1.0);
  const double s = std::min(y, std::sqrt(0.5 * (1 - y)));
  const double as = s * polynomial(detail::kAsin, s * s);
  const double far = y > 0.5;  // 1: asin(y) = pi/2 - 2 asin(s)
  return std::copysign(as + far * (0.5 * kPi - 3 * as), x);
}

}  // namespace mcref
