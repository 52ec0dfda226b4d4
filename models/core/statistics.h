#pragma once
// Distribution functions for statistical tests and verdicts: normal,
// Student t, chi-squared, Sidak bounds. Header-only (used by validate/ and tests).
#include <cmath>
#include <limits>

#include "models/core/vec.h"

namespace mcref {

// Standard error of the mean of n samples from their sum and sum of squares.
// A value identical in every sample leaves only rounding in sum_sq - n mean^2,
// which grows with the count of summed terms (up to ~n eps sum_sq): a
// variance below 64 eps sum_sq / min(n, 64) counts as 0.
inline double stderr_of_mean(double sum, double sum_sq, double n) {
  if (std::isnan(sum) || std::isnan(sum_sq)) return NAN;  // an empty cell: no error bar, not a zero one
  const double mean = sum / n;
  double var = std::fmax(0.0, (sum_sq - n * mean * mean) / (n - 1));
  if (var <= 64 * 2.220446049250313e-16 * sum_sq / std::fmin(n, 64.0)) var = 0;
  return std::sqrt(var / n);
}

inline double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

inline double normal_quantile(double p) {
  if (p <= 0) return -std::numeric_limits<double>::infinity();
  if (p >= 1) return std::numeric_limits<double>::infinity();
  // Acklam's rational approximation, then two Newton steps on erfc.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  double x;
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p > 1 - 0.02425) {
    const double q = std::sqrt(-2 * std::log1p(-p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  for (int it = 0; it < 2; ++it) {
    const double e = normal_cdf(x) - p;
    const double u = e * std::sqrt(2 * kPi) * std::exp(x * x / 2);
    x -= u / (1 + x * u / 2);
  }
  return x;
}

namespace detail {
// Continued fraction for the incomplete beta (Lentz).
inline double beta_fraction(double x, double a, double b) {
  const double tiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m < 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1) * (a + m2));
    d = 1 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1));
    d = 1 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-15) break;
  }
  return h;
}
}  // namespace detail

inline double regularized_beta(double x, double a, double b) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double ln_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1) / (a + b + 2)) return std::exp(ln_front) * detail::beta_fraction(x, a, b) / a;
  return 1 - std::exp(ln_front) * detail::beta_fraction(1 - x, b, a) / b;
}

inline double regularized_gamma_q(double a, double x) {
  if (x <= 0) return 1;
  const double ln_front = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {  // series for P
    double sum = 1 / a, term = sum;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
    }
    return 1 - std::exp(ln_front) * sum;
  }
  // Continued fraction for Q (Lentz).
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-16) break;
  }
  return std::exp(ln_front) * h;
}

inline double student_t_cdf(double t, double nu) {
  const double x = nu / (nu + t * t);
  const double tail = 0.5 * regularized_beta(x, nu / 2, 0.5);
  return t >= 0 ? 1 - tail : tail;
}

inline double chi2_survival(double x, double k) { return regularized_gamma_q(k / 2, x / 2); }

// Probability-preserving map of a Student-t value with nu degrees of freedom to
// N(0, 1), made on the tail P(T > |t|) = I_{nu/(nu+t^2)}(nu/2, 1/2) / 2 for
// precision; t itself for nu >= 1e7, or where the tail is beyond double range.
inline double t_to_normal(double t, double nu) {
  if (!(nu < 1e7)) return t;
  const double tail = 0.5 * regularized_beta(nu / (nu + t * t), nu / 2, 0.5);
  const double z = std::copysign(-normal_quantile(tail), t);
  return std::isfinite(z) ? z : t;
}

// Welch–Satterthwaite degrees of freedom of the difference of two means with
// standard errors a and b from na and nb samples (batches).
inline double welch_dof(double a, double b, double na, double nb) {
  const double a2 = a * a, b2 = b * b;
  return (a2 + b2) * (a2 + b2) / (a2 * a2 / (na - 1) + b2 * b2 / (nb - 1));
}

// Šidák: the level of each of n tests for a family-wise level alpha, 1 - (1 - alpha)^(1/n).
inline double sidak_per_test(double alpha, double n) { return -std::expm1(std::log1p(-alpha) / n); }

inline double sidak_z_bound(double alpha, double n) {
  const double per_cell = sidak_per_test(alpha, n);
  return normal_quantile(1 - per_cell / 2);
}


// Regularised lower incomplete gamma P(a, x) = 1 - Q(a, x).
inline double regularized_gamma_p(double a, double x) { return 1 - regularized_gamma_q(a, x); }

}  // namespace mcref
