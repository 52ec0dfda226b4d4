#pragma once
// Polynomials with constant coefficients, evaluated by Estrin's scheme: pairs
// c[k] + c[k+1] z, then pairs of those with z^2, ... (dependency chains of
// log2(N) steps rather than Horner's N).
#include <array>
#include <cstddef>

namespace mcref {

namespace detail {
template <std::size_t N>
inline double estrin(const double* c, double z) {
  if constexpr (N == 1) {
    return c[0];
  } else {
    constexpr std::size_t H = [] {  // the largest power of two below N
      std::size_t h = 1;
      while (2 * h < N) h *= 2;
      return h;
    }();
    double zh = z;  // z^H
    for (std::size_t k = 1; k < H; k *= 2) zh *= zh;
    return estrin<H>(c, z) + zh * estrin<N - H>(c + H, z);
  }
}
}  // namespace detail

// sum_{k < N} c[k] z^k.
template <std::size_t N>
inline double polynomial(const std::array<double, N>& c, double z) {
  return detail::estrin<N>(c.data(), z);
}

}  // namespace mcref
