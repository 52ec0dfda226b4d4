#include "models/lambert_sphere/phase_sampling.h"

#include <cmath>

#include "models/core/frame.h"
#include "models/lambert_sphere/phase_function.h"

namespace mcref::lambert_sphere {

namespace {

// Q(t) = 1 - F(cos t) = (4t + 2t cos 2t - 3 sin 2t) / (6 pi), t in [0, pi].
double forward_tail(double t) {
  if (t < 0.5) {
    // With u = 2t: 4t + 2t cos 2t - 3 sin 2t = sum_{n>=2} (-1)^n (2n-2) u^(2n+1) / (2n+1)!.
    const double u = 2 * t, u2 = u * u;
    double term = u * u2 * u2 / 120.0;  // u^5 / 5!
    double s = 0;
    for (int n = 2; n < 14; ++n) {
      s += (2 * n - 2) * term;
      term *= -u2 / ((2 * n + 2) * (2 * n + 3));
    }
    return s / (6 * kPi);
  }
  return (4 * t + 2 * t * std::cos(2 * t) - 3 * std::sin(2 * t)) / (6 * kPi);
}

}  // namespace

double phase_pdf_mu(double mu) { return 2 * kPi * phase_function(mu); }

double phase_cdf_mu(double mu) {
  if (mu <= -1) return 0.0;
  if (mu >= 1) return 1.0;
  return 1 - forward_tail(std::acos(mu));
}

double phase_ccdf_mu(double mu) {
  if (mu <= -1) return 1.0;
  if (mu >= 1) return 0.0;
  return forward_tail(std::acos(mu));
}

double phase_inverse_cdf(double xi) {
  if (xi <= 0) return -1.0;
  if (xi >= 1) return 1.0;
  // Solve Q(t) = 1 - xi for t in [0, pi]; Q increases, Q'(t) = 4 (sin t - t cos t) sin t / (3 pi).
  const double target = 1 - xi;
  double lo = 0, hi = kPi, t = std::acos(1 - 2 * xi);
  for (int it = 0; it < 200; ++it) {
    const double g = forward_tail(t) - target;
    if (g < 0) lo = t; else hi = t;
    const double dq = 4 * (std::sin(t) - t * std::cos(t)) * std::sin(t) / (3 * kPi);
    double next = dq > 0 ? t - g / dq : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - t) < 1e-15 * (1 + t) || hi - lo < 1e-15) {
      t = next;
      break;
    }
    t = next;
  }
  return std::cos(t);
}

double sample_phase_cosine_exact(double u1, double u2, double u3) {
  return std::sqrt((1 - u1) * (1 - u2)) * std::sin(2 * kPi * u3) - std::sqrt(u1 * u2);
}

double sample_phase_cosine_approx(double xi) {
  return 1 - 2 * std::pow(1 - std::pow(xi, 0.0401885 * xi + 1.01938), 0.397225);
}

InverseCdfError approximate_inverse_cdf_max_error(int grid_points) {
  auto err = [](double xi) { return std::fabs(sample_phase_cosine_approx(xi) - phase_inverse_cdf(xi)); };
  InverseCdfError best;
  for (int i = 0; i <= grid_points; ++i) {
    const double xi = static_cast<double>(i) / grid_points, e = err(xi);
    if (e > best.max_abs_error) best = {e, xi};
  }
  // Golden-section refinement of the maximum within one grid step.
  const double step = 1.0 / grid_points, r = 0.5 * (std::sqrt(5.0) - 1);
  double a = std::fmax(0.0, best.xi - step), b = std::fmin(1.0, best.xi + step);
  double x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = err(x1), f2 = err(x2);
  for (int it = 0; it < 80; ++it) {
    if (f1 > f2) { b = x2; x2 = x1; f2 = f1; x1 = b - r * (b - a); f1 = err(x1); }
    else { a = x1; x1 = x2; f1 = f2; x2 = a + r * (b - a); f2 = err(x2); }
  }
  if (f1 > best.max_abs_error) best = {f1, x1};
  if (f2 > best.max_abs_error) best = {f2, x2};
  return best;
}

Vec3 scattered_direction(const Vec3& propagation, double mu, double u_phi) {
  const double s = std::sqrt(std::fmax(0.0, 1 - mu * mu)), phi = 2 * kPi * u_phi;
  return Frame(propagation).to_world({s * std::cos(phi), s * std::sin(phi), mu});
}

}  // namespace mcref::lambert_sphere
