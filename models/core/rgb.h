#pragma once
// RGB throughput: all channels are carried by one walk where the geometry is shared.
#include <algorithm>

namespace mcref {

struct Rgb {
  double r = 0, g = 0, b = 0;
  constexpr Rgb() = default;
  constexpr Rgb(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}
  constexpr explicit Rgb(double v) : r(v), g(v), b(v) {}
  constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr double max() const { return std::max(r, std::max(g, b)); }
  constexpr double mean() const { return (r + g + b) / 3; }
  constexpr bool is_zero() const { return r == 0 && g == 0 && b == 0; }
};

constexpr Rgb operator+(Rgb a, Rgb b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
constexpr Rgb operator-(Rgb a, Rgb b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
constexpr Rgb operator*(Rgb a, Rgb b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
constexpr Rgb operator*(Rgb a, double s) { return {a.r * s, a.g * s, a.b * s}; }
constexpr Rgb operator*(double s, Rgb a) { return a * s; }
constexpr Rgb operator/(Rgb a, double s) { return {a.r / s, a.g / s, a.b / s}; }

}  // namespace mcref
