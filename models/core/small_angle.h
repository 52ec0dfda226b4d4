#pragma once
// sin and cos of a small angle by their Taylor series (to d^17 and d^18):
// error below 2e-14 for |d| <= 1.5, at about a third of the cost of
// std::sin + std::cos. Larger angles fall back to the library.
// sincos_turn: sin and cos of 2 pi u (a fraction u of a turn, e.g. a uniform
// random number) through an exact reduction to the nearest quarter turn.
#include <array>
#include <cmath>
#include <cstdint>

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
}  // namespace detail

namespace detail {
// The series of sincos_small, without its range check.
inline SinCos sincos_series(double d) {
  // Estrin's scheme in z (shorter dependency chains than Horner's).
  const double z = d * d, z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  const double s = (kSin[0] + kSin[1] * z) + z2 * (kSin[2] + kSin[3] * z) +
                   z4 * ((kSin[4] + kSin[5] * z) + z2 * (kSin[6] + kSin[7] * z)) + z8 * kSin[8];
  const double c = (kCos[0] + kCos[1] * z) + z2 * (kCos[2] + kCos[3] * z) +
                   z4 * ((kCos[4] + kCos[5] * z) + z2 * (kCos[6] + kCos[7] * z)) + z8 * (kCos[8] + kCos[9] * z);
  return {d * s, c};
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
