#include "models/lambert_sphere/mode_constants.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "models/core/vec.h"
#include "models/lambert_sphere/h_functions.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/radiative_transfer/three_term_half_space.h"

namespace mcref::lambert_sphere {

FirstModeConstants first_mode_constants_fit(double c) {
  return {-0.00473696 * c * c - 0.0589037 * c, 0.44038 * c + 1};
}

ZerothModeConstants zeroth_mode_constants_fit(double c) {
  const double s = std::sqrt(1 - c), q = 1 - c, q15 = q * s;
  ZerothModeConstants k;
  k.A = 69 * c / 128;                                           // Eq. 33
  k.E = 15.0 / 128.0 * (1 - c) * c * (4 * c / 3 + 3);            // Eq. 33
  k.B = (0.346689 * q15 - 0.777574 * q + 0.515357 * s - 0.084463) /
        (0.182602 * q - 0.665502 * s + 0.964893);                // Eq. 34
  k.C = (-5602.45 * q15 + 7487.99 * q - 2567.74 * s + 682.848) /
        (1480.25 * q - 4008.33 * s + 5850.6);                    // Eq. 35
  k.D = (166.883 * q15 - 327.428 * q + 160.397 * s + 0.285529) /
        (596.423 * q - 412.984 * s + 674.191);                   // Eq. 36
  k.F = (266.063 * q15 - 21.9141 * q - 242.16 * s - 1.9209) /
        (215.773 * q + 457.42 * s + 1499.9);                     // Eq. 37
  return k;
}

namespace {

// Least squares for N unknowns by normal equations + Gauss-Jordan with pivoting.
template <int N>
std::array<double, N> least_squares(const std::vector<std::pair<std::array<double, N>, double>>& rows) {
  double a[N][N + 1] = {};
  for (const auto& [phi, y] : rows)
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < N; ++j) a[i][j] += phi[i] * phi[j];
      a[i][N] += phi[i] * y;
    }
  for (int i = 0; i < N; ++i) {
    int p = i;
    for (int r = i + 1; r < N; ++r)
      if (std::fabs(a[r][i]) > std::fabs(a[p][i])) p = r;
    for (int j = 0; j <= N; ++j) std::swap(a[i][j], a[p][j]);
    for (int r = 0; r < N; ++r)
      if (r != i) {
        const double f = a[r][i] / a[i][i];
        for (int j = i; j <= N; ++j) a[r][j] -= f * a[i][j];
      }
  }
  std::array<double, N> x{};
  for (int i = 0; i < N; ++i) x[i] = a[i][N] / a[i][i];
  return x;
}

constexpr double kGrid[6] = {0.05, 0.2, 0.4, 0.6, 0.8, 1.0};

}  // namespace

ZerothModeConstants zeroth_mode_constants_exact(double c) {
  if (!(c > 0 && c < 1)) throw std::invalid_argument("zeroth_mode_constants_exact: c must be in (0, 1)");
  const radiative_transfer::ThreeTermHalfSpace mode(c, legendre_coefficient(1), legendre_coefficient(2), 0);
  const radiative_transfer::HTable h = h_table(0, c);
  std::vector<std::pair<std::array<double, 6>, double>> rows;
  for (double a : kGrid)
    for (double b : kGrid) {
      const double y = mode.mode(a, b) * 2 * kPi * (a + b) / (h(a) * h(b));
      rows.push_back({{1, a + b, a * b, a * b * (a + b), a * a * b * b, a * a + b * b}, y});
    }
  const auto x = least_squares<6>(rows);
  return {x[0], x[1], x[2], x[3], x[4], x[5]};
}

ExactFirstModeConstants first_mode_constants_exact(double c) {
  if (!(c > 0 && c <= 1)) throw std::invalid_argument("first_mode_constants_exact: c must be in (0, 1]");
  const radiative_transfer::ThreeTermHalfSpace mode(c, legendre_coefficient(1), legendre_coefficient(2), 1);
  const radiative_transfer::HTable h = h_table(1, c);
  // f^(1) 6 pi (a + b) / (c H1(a) H1(b) S) = scale (1 + q a b + l (a + b)), q = l^2 + 45 m / 64.
  std::vector<std::pair<std::array<double, 3>, double>> rows;
  for (double a : kGrid)
    for (double b : kGrid) {
      if (a >= 1 || b >= 1) continue;  // S = 0
      const double s = std::sqrt((1 - a * a) * (1 - b * b));
      const double y = mode.mode(a, b) * 6 * kPi * (a + b) / (c * h(a) * h(b) * s);
      rows.push_back({{1, a * b, a + b}, y});
    }
  const auto x = least_squares<3>(rows);
  ExactFirstModeConstants k;
  k.scale = x[0];
  k.l = x[2] / x[0];
  const double q = x[1] / x[0];
  k.m = (q - k.l * k.l) * 64.0 / 45.0;
  return k;
}

}  // namespace mcref::lambert_sphere
