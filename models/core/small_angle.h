#pragma once
// sin and cos of a small angle by their Taylor series (to d^17 and d^18):
// error below 2e-14 for |d| <= 1.5, at about a third of the cost of
// std::sin + std::cos. Larger angles fall back to the library.
// sincos_within_pi: sin and cos of |x| <= pi by the series to d^19 and d^20
// about pi/2 (|d| <= pi/2, error below 1e-15).
// sincos_turn: sin and cos of 2 pi u (a fraction u of a turn, e.g. a uniform
// random number) through an exact reduction to the nearest quarter turn.
#include <array>
#include <cmath>
#include <cstdint>

#include "models/core/polynomial.h"
#include "models/core/vec.h"

namespace mcref {

struct SinCos {
  double sin, cos;
};

namespace detail {
// Taylor coefficients in z = d^2: (-1)^k / (2k + first)!.
template <int N>
constexpr std::array<double, N> series(int first) {
  std::array<double, N> a{};
  for (int k = 0; k < N; ++k) {
    double f = 1;
    for (int n = 2; n <= 2 * k + first; ++n) f *= n;
    a[k] = (k % 2 ? -1 : 1) / f;
  }
  return a;
}
inline constexpr std::array<double, 9> kSin = series<9>(1);   // to d^17
inline constexpr std::array<double, 10> kCos = series<10>(0);  // to d^18
inline constexpr std::array<double, 10> kSinWide = series<10>(1);  // to d^19
inline constexpr std::array<double, 11> kCosWide = series<11>(0);  // to d^20
}  // namespace detail

inline SinCos sincos_small(double d) {
  if (!(std::fabs(d) <= 1.5)) return {std::sin(d), std::cos(d)};
  const double z = d * d;
  return {d * polynomial(detail::kSin, z), polynomial(detail::kCos, z)};
}

// sin x and cos x for |x| <= pi (else the library): the series about pi/2,
// sin x = cos(|x| - pi/2) with the sign of x, cos x = -sin(|x| - pi/2).
inline SinCos sincos_within_pi(double x) {
  if (!(std::fabs(x) <= kPi)) return {std::sin(x), std::cos(x)};
  const double d = std::fabs(x) - 0.5 * kPi, z = d * d;
  return {std::copysign(polynomial(detail::kCosWide, z), x), -d * polynomial(detail::kSinWide, z)};
}

// sin(2 pi u) and cos(2 pi u), within ~1e-15; by the series for
// 0 <= u < 2^50 (u - q/4 is then exact and |d| <= pi/4), else the library.
inline SinCos sincos_turn(double u) {
  if (!(u >= 0 && u < 0x1p50)) return {std::sin(2 * kPi * u), std::cos(2 * kPi * u)};
  const std::int64_t q = static_cast<std::int64_t>(4 * u + 0.5);  // nearest quarter turn for u >= 0
  const SinCos r = sincos_small(2 * kPi * (u - 0.25 * static_cast<double>(q)));
  // Rotate by q quarter turns: cos(d + q pi/2) = v[-q mod 4], sin(d + q pi/2) = v[(1 - q) mod 4].
  const double v[4] = {r.cos, r.sin, -r.cos, -r.sin};
  return {v[(1 - q) & 3], v[-q & 3]};
}

}  // namespace mcref
