#pragma once
// 3-vectors in double precision. z is the macro normal (DESIGN.md conventions).
#include <cmath>

namespace mcref {

inline constexpr double kPi = 3.14159265358979323846;

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3 operator*(double s, Vec3 a) { return a * s; }
constexpr Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr Vec3 mul(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3 div(Vec3 a, Vec3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
constexpr double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return a / length(a); }

// Direction from spherical angles (theta from +z, phi from +x).
inline Vec3 spherical_direction(double theta, double phi) {
  const double s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}
inline double spherical_theta(Vec3 d) { return std::acos(std::fmin(1.0, std::fmax(-1.0, d.z))); }
// Azimuth in [0, 2pi).
inline double spherical_phi(Vec3 d) {
  const double p = std::atan2(d.y, d.x);
  return p < 0 ? p + 2 * kPi : p;
}
inline double deg_to_rad(double d) { return d * kPi / 180.0; }
// Relative azimuth phi - phi_ref in [0, 2pi), or folded into [0, pi].
inline double relative_azimuth(double phi, double phi_ref, bool folded) {
  double d = std::fmod(phi - phi_ref, 2 * kPi);
  if (d < 0) d += 2 * kPi;
  if (folded && d > kPi) d = 2 * kPi - d;
  return d;
}

}  // namespace mcref
