#include "models/radiative_transfer/three_term_half_space.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "models/core/quadrature.h"
#include "models/core/vec.h"

namespace mcref::radiative_transfer {

namespace {
constexpr int kLevels = 30;        // panels [2^-(j+1), 2^-j], j = 1..kLevels, plus [0, 2^-(kLevels+1)]
constexpr int kPanelPoints = 8;
constexpr int kThetaPoints = 12;   // two panels in theta = acos(mu) over mu in [1/2, 1]
}  // namespace

ThreeTermHalfSpace::ThreeTermHalfSpace(double albedo, double a1, double a2, int order, Options options)
    : c_(albedo), a1_(a1), a2_(a2), gamma_(order == 0 ? 2 * kPi : kPi), order_(order) {
  if (order < 0 || order > 2)
    throw std::invalid_argument("ThreeTermHalfSpace: order must be 0, 1 or 2");
  if (!(albedo >= 0 && albedo <= 1) || (order == 0 && albedo >= 1))
    throw std::invalid_argument("ThreeTermHalfSpace: albedo must be in [0, 1) (m = 0) or [0, 1]");
  // Separable kernels p+-(a, b) = u(a)^T M(+-) u(b) of Fourier order m.
  const double f = 1 / (4 * kPi);
  for (int s = 0; s < 2; ++s) {
    const double eps = s == 0 ? 1.0 : -1.0;
    auto& m = s == 0 ? m_plus_ : m_minus_;
    if (order == 0) {  // u = (1, a, a^2)
      rank_ = 3;
      m[0][0] = f * (1 + a2 / 4);
      m[1][1] = f * eps * a1;
      m[2][2] = f * 9 * a2 / 4;
      m[0][2] = m[2][0] = -f * 3 * a2 / 4;
    } else if (order == 1) {  // u = (s_a, a s_a), s_a = sqrt(1 - a^2)
      rank_ = 2;
      m[0][0] = f * eps * a1;
      m[1][1] = f * 3 * a2;
    } else {  // u = (1 - a^2)
      rank_ = 1;
      m[0][0] = f * 3 * a2 / 4;
    }
  }
  // Nystrom nodes.
  const GaussLegendre panel(kPanelPoints), arc(kThetaPoints);
  auto add = [&](const GaussLegendre& rule, double lo, double hi, bool theta) {
    const double h = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
    for (std::size_t i = 0; i < rule.x.size(); ++i) {
      const double v = mid + h * rule.x[i];
      mu_.push_back(theta ? std::cos(v) : v);
      w_.push_back(h * rule.w[i] * (theta ? std::sin(v) : 1.0));
    }
  };
  add(panel, 0.0, std::ldexp(1.0, -(kLevels + 1)), false);
  for (int j = kLevels; j >= 1; --j) add(panel, std::ldexp(1.0, -(j + 1)), std::ldexp(1.0, -j), false);
  add(arc, kPi / 6, kPi / 3, true);
  add(arc, 0.0, kPi / 6, true);
  const std::size_t n = mu_.size();
  u_.resize(n);
  for (std::size_t i = 0; i < n; ++i) u_[i] = basis(mu_[i]);

  // Precomputed single-scattering source c p-(i, k) / (mu_i + mu_k) and M+ u_k.
  std::vector<double> source(n * n);
  std::vector<Vec> mpu(n);
  for (std::size_t i = 0; i < n; ++i) {
    mpu[i] = apply(u_[i], +1);
    for (std::size_t k = 0; k < n; ++k)
      source[i * n + k] = c_ * kernel(u_[i], u_[k], -1) / (mu_[i] + mu_[k]);
  }
  x_.assign(n, Vec{0, 0, 0});
  std::vector<Vec> next(n), mpx(n), mmx(n);
  // Fixed point X = G(X). Anderson(1): with residuals r = G(X) - X,
  // X <- G(X) - b (G(X) - G(X_prev)), b = r.(r - r_prev) / |r - r_prev|^2.
  std::vector<Vec> prev_x, prev_g;
  double residual = 1;
  for (iterations_ = 1; iterations_ <= options.max_iterations; ++iterations_) {
    for (std::size_t k = 0; k < n; ++k) {
      mpx[k] = apply(x_[k], +1);
      mmx[k] = apply(x_[k], -1);
    }
    for (std::size_t i = 0; i < n; ++i) {
      Vec acc{0, 0, 0};
      const double a = mu_[i];
      for (std::size_t k = 0; k < n; ++k) {
        const double b = mu_[k];
        double t1 = 0, t2 = 0, t3 = 0;
        for (int r = 0; r < rank_; ++r) {
          t1 += u_[i][r] * mpx[k][r];
          t2 += x_[i][r] * mpu[k][r];
          t3 += x_[i][r] * mmx[k][r];
        }
        const double fik = source[i * n + k] +
                           c_ * (gamma_ * (b * t1 + a * t2) + gamma_ * gamma_ * a * b * t3) / (a + b);
        const double wf = w_[k] * fik;
        for (int r = 0; r < rank_; ++r) acc[r] += wf * u_[k][r];
      }
      next[i] = acc;
    }
    // Residual and Anderson(1) step.
    double diff = 0, scale = 1e-300, num = 0, den = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (int r = 0; r < rank_; ++r) {
        const double d = next[i][r] - x_[i][r];
        diff = std::fmax(diff, std::fabs(d));
        scale = std::fmax(scale, std::fabs(next[i][r]));
        if (!prev_x.empty()) {  // empty on the first iteration
          const double dd = d - (prev_g[i][r] - prev_x[i][r]);
          num += d * dd;
          den += dd * dd;
        }
      }
    residual = diff / scale;
    if (residual < options.tolerance) {
      x_ = next;
      break;
    }
    const double beta = (options.anderson && !prev_x.empty() && den > 0) ? num / den : 0.0;
    prev_x.resize(n);
    prev_g.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec gi = next[i];
      Vec xi = gi;
      if (beta != 0)
        for (int r = 0; r < rank_; ++r) xi[r] = gi[r] - beta * (gi[r] - prev_g[i][r]);
      prev_x[i] = x_[i];
      prev_g[i] = gi;
      x_[i] = xi;
    }
  }
  if (!(residual < options.tolerance))
    throw std::invalid_argument("ThreeTermHalfSpace: no convergence after " +
                                std::to_string(options.max_iterations) + " iterations (residual " +
                                std::to_string(residual) + ")");
}

ThreeTermHalfSpace::Vec ThreeTermHalfSpace::basis(double mu) const {
  const double s = std::sqrt(std::fmax(0.0, 1 - mu * mu));
  if (order_ == 0) return {1.0, mu, mu * mu};
  if (order_ == 1) return {s, mu * s, 0.0};
  return {s * s, 0.0, 0.0};
}

ThreeTermHalfSpace::Vec ThreeTermHalfSpace::apply(const Vec& v, int sign) const {
  const auto& m = sign > 0 ? m_plus_ : m_minus_;
  Vec out{0, 0, 0};
  for (int r = 0; r < rank_; ++r)
    for (int q = 0; q < rank_; ++q) out[r] += m[r][q] * v[q];
  return out;
}

double ThreeTermHalfSpace::kernel(const Vec& ua, const Vec& ub, int sign) const {
  const Vec mb = apply(ub, sign);
  double s = 0;
  for (int r = 0; r < rank_; ++r) s += ua[r] * mb[r];
  return s;
}

double ThreeTermHalfSpace::mode_from(double mu_i, const Vec& ui, const Vec& xi, double mu_o, const Vec& uo,
                                     const Vec& xo) const {
  const Vec mpxo = apply(xo, +1), mpuo = apply(uo, +1), mmxo = apply(xo, -1);
  double t1 = 0, t2 = 0, t3 = 0;
  for (int r = 0; r < rank_; ++r) {
    t1 += ui[r] * mpxo[r];
    t2 += xi[r] * mpuo[r];
    t3 += xi[r] * mmxo[r];
  }
  return c_ * (kernel(ui, uo, -1) + gamma_ * (mu_o * t1 + mu_i * t2) + gamma_ * gamma_ * mu_i * mu_o * t3) /
         (mu_i + mu_o);
}

ThreeTermHalfSpace::Vec ThreeTermHalfSpace::moments_at(double mu) const {
  // X(mu) = sum_k w_k u_k f(mu, mu_k), f linear in X(mu): f = alpha_k + beta_k . X(mu).
  const Vec u = basis(mu);
  double a[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, rhs[3] = {0, 0, 0};
  for (std::size_t k = 0; k < mu_.size(); ++k) {
    const double b = mu_[k], inv = c_ / (mu + b);
    const Vec mpx = apply(x_[k], +1), mpu = apply(u_[k], +1), mmx = apply(x_[k], -1);
    double t1 = 0;
    for (int r = 0; r < rank_; ++r) t1 += u[r] * mpx[r];
    const double alpha = inv * (kernel(u, u_[k], -1) + gamma_ * b * t1);
    Vec beta{0, 0, 0};
    for (int r = 0; r < rank_; ++r) beta[r] = inv * (gamma_ * mu * mpu[r] + gamma_ * gamma_ * mu * b * mmx[r]);
    for (int r = 0; r < rank_; ++r) {
      rhs[r] += w_[k] * u_[k][r] * alpha;
      for (int q = 0; q < rank_; ++q) a[r][q] -= w_[k] * u_[k][r] * beta[q];
    }
  }
  // Gaussian elimination with partial pivoting on the rank_ x rank_ system.
  int idx[3] = {0, 1, 2};
  for (int col = 0; col < rank_; ++col) {
    int piv = col;
    for (int r = col + 1; r < rank_; ++r)
      if (std::fabs(a[idx[r]][col]) > std::fabs(a[idx[piv]][col])) piv = r;
    std::swap(idx[col], idx[piv]);
    for (int r = col + 1; r < rank_; ++r) {
      const double f = a[idx[r]][col] / a[idx[col]][col];
      for (int q = col; q < rank_; ++q) a[idx[r]][q] -= f * a[idx[col]][q];
      rhs[idx[r]] -= f * rhs[idx[col]];
    }
  }
  Vec x{0, 0, 0};
  for (int col = rank_ - 1; col >= 0; --col) {
    double s = rhs[idx[col]];
    for (int q = col + 1; q < rank_; ++q) s -= a[idx[col]][q] * x[q];
    x[col] = s / a[idx[col]][col];
  }
  return x;
}

double ThreeTermHalfSpace::mode(double mu_i, double mu_o) const {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  const Vec xi = moments_at(mu_i), xo = moments_at(mu_o);
  return mode_from(mu_i, basis(mu_i), xi, mu_o, basis(mu_o), xo);
}

double ThreeTermHalfSpace::single_scattering_mode(double mu_i, double mu_o) const {
  if (!(mu_i > 0 && mu_o > 0)) return 0.0;
  return c_ * kernel(basis(mu_i), basis(mu_o), -1) / (mu_i + mu_o);
}

}  // namespace mcref::radiative_transfer
