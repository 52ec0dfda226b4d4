#include "models/sggx/mat3.h"

#include <algorithm>
#include <cmath>

namespace mcref::sggx {

Mat3 identity3() { return diagonal(1, 1, 1); }

Mat3 diagonal(double a, double b, double c) {
  Mat3 r;
  r.m[0][0] = a;
  r.m[1][1] = b;
  r.m[2][2] = c;
  return r;
}

Mat3 outer(Vec3 a, Vec3 b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a[i] * b[j];
  return r;
}

Mat3 from_columns(Vec3 c0, Vec3 c1, Vec3 c2) {
  Mat3 r;
  for (int i = 0; i < 3; ++i) {
    r.m[i][0] = c0[i];
    r.m[i][1] = c1[i];
    r.m[i][2] = c2[i];
  }
  return r;
}

Mat3 operator+(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] + b.m[i][j];
  return r;
}

Mat3 operator*(const Mat3& a, double s) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] * s;
  return r;
}

Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}

double determinant(const Mat3& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Mat3 inverse(const Mat3& a) {
  const auto& m = a.m;
  Mat3 r;
  r.m[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  r.m[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
  r.m[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
  r.m[1][0] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  r.m[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
  r.m[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
  r.m[2][0] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  r.m[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
  r.m[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  return r * (1.0 / determinant(a));
}

bool cholesky_lower(const Mat3& a, Mat3& l) {
  l = Mat3{};
  const double scale = std::max({std::fabs(a.m[0][0]), std::fabs(a.m[1][1]), std::fabs(a.m[2][2])});
  if (!(scale > 0)) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j)
      if (std::fabs(a.m[i][j] - a.m[j][i]) > 1e-12 * scale) return false;
  for (int j = 0; j < 3; ++j) {
    double d = a.m[j][j];
    for (int k = 0; k < j; ++k) d -= l.m[j][k] * l.m[j][k];
    if (!(d > 1e-300)) return false;
    l.m[j][j] = std::sqrt(d);
    for (int i = j + 1; i < 3; ++i) {
      double s = a.m[i][j];
      for (int k = 0; k < j; ++k) s -= l.m[i][k] * l.m[j][k];
      l.m[i][j] = s / l.m[j][j];
    }
  }
  return true;
}

double max_abs_difference(const Mat3& a, const Mat3& b) {
  double d = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d = std::max(d, std::fabs(a.m[i][j] - b.m[i][j]));
  return d;
}

}  // namespace mcref::sggx
