#pragma once
// Polynomials with constant coefficients, evaluated by Estrin's scheme: pairs
// c[k] + c[k+1] z, then pairs of those with z^2, ... (dependency chains of
// log2(N) steps rather than Horner's N).
#include <array>
#include <cstddef>

namespace mcref {

namespace detail {
// z^H for H a power of two, by repeated squaring (no loop: a loop inside the
// wave walk's lane loops stops GCC's vectoriser, sim/slab/wave_walk.cpp).
template <std::size_t H>
inline double squarings(double z) {
  if constexpr (H == 1) {
    return z;
  } else {
    const double h = squarings<H / 2>(z);
    return h * h;
  }
}

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
    return estrin<H>(c, z) + squarings<H>(z) * estrin<N - H>(c + H, z);
  }
}
}  // namespace detail

// sum_{k < N} c[k] z^k.
template <std::size_t N>
inline double polynomial(const std::array<double, N>& c, double z) {
  return detail::estrin<N>(c.data(), z);
}

}  // namespace mcref
