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

namespace detail {
// The series of sincos_small, without its range check.
inline SinCos sincos_series(double d) {
  const double z = d * d;
  return {d * polynomial(kSin, z), polynomial(kCos, z)};
}
// sin and cos of d + q pi/2 from those of d, by selects (no table, no branch):
// cos(d + q pi/2) = {c, -s, -c, s}[q mod 4], sin(d + q pi/2) = {s, c, -s, -c}[q mod 4].
inline SinCos rotate_quarter_turns(SinCos r, int q) {
  const bool odd = q & 1;
  const double s = odd ? r.cos : r.sin, c = odd ? r.sin : r.cos;
  return {q & 2 ? -s : s, (q + 1) & 2 ? -c : c};
}
}  // namespace detail

inline SinCos sincos_small(double d) {
  if (!(std::fabs(d) <= 1.5)) return {std::sin(d), std::cos(d)};
  return detail::sincos_series(d);
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
  const SinCos r = detail::sincos_series(2 * kPi * (u - 0.25 * static_cast<double>(q)));
  return detail::rotate_quarter_turns(r, static_cast<int>(q & 3));
}

// The same for 0 <= u <= 1 (a uniform random number), bit for bit, without
// the range check: no branch and no library call, so loops over many u
// vectorise.
inline SinCos sincos_turn_unit(double u) {
  const int q = static_cast<int>(4 * u + 0.5);
  return detail::rotate_quarter_turns(detail::sincos_series(2 * kPi * (u - 0.25 * q)), q);
}

}  // namespace mcref
