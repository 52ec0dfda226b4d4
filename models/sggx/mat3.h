#pragma once
// A small 3x3 matrix for SGGX matrices S (symmetric positive definite) and the
// rotations/factors built from them. Row-major, double precision.
#include "models/core/vec.h"

namespace mcref::sggx {

struct Mat3 {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double operator()(int r, int c) const { return m[r][c]; }
  double& operator()(int r, int c) { return m[r][c]; }
};

Mat3 identity3();
Mat3 diagonal(double a, double b, double c);
// Outer product a b^T.
Mat3 outer(Vec3 a, Vec3 b);
// Matrix whose columns are c0, c1, c2.
Mat3 from_columns(Vec3 c0, Vec3 c1, Vec3 c2);
inline Mat3 transpose(const Mat3& a) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}
Mat3 operator+(const Mat3& a, const Mat3& b);
Mat3 operator*(const Mat3& a, double s);
Mat3 operator*(const Mat3& a, const Mat3& b);
inline Vec3 operator*(const Mat3& a, Vec3 v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
double determinant(const Mat3& a);
// Inverse by the adjugate; the caller guarantees det != 0.
Mat3 inverse(const Mat3& a);
// v^T A v.
inline double quadratic_form(const Mat3& a, Vec3 v) { return dot(v, a * v); }
// Lower-triangular L with A = L L^T. Returns false (and leaves L unspecified)
// when A is not symmetric positive definite to working precision.
bool cholesky_lower(const Mat3& a, Mat3& lower);
// Largest |a_ij - b_ij|.
double max_abs_difference(const Mat3& a, const Mat3& b);

}  // namespace mcref::sggx
