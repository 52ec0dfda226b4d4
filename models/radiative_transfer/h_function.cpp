#include "models/radiative_transfer/h_function.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "models/core/quadrature.h"
#include "models/core/vec.h"

namespace mcref::radiative_transfer {

namespace {

// Appends the nodes of `rule` mapped to [a, b]; weights times f(x).
template <class F>
void append_panel(const GaussLegendre& rule, double a, double b, F&& f, std::vector<double>& x,
                  std::vector<double>& wf) {
  const double h = 0.5 * (b - a), c = 0.5 * (b + a);
  for (std::size_t i = 0; i < rule.x.size(); ++i) {
    const double xi = c + h * rule.x[i];
    x.push_back(xi);
    wf.push_back(h * rule.w[i] * f(xi));
  }
}

// Panels of Fock's theta integral: ends at theta_j = atan(mu 2^j), from
// t = 2^kLowExponent to t = 2^6 / mu (then to pi/2); kThetaPoints each.
constexpr int kLowExponent = -52;
constexpr int kThetaPoints = 16;

}  // namespace

Dispersion::Dispersion(const CharacteristicFunction& psi) {
  const GaussLegendre rule(12);
  append_panel(rule, 0.0, 0.5, psi, x_near_, wpsi_near_);
  append_panel(rule, 0.5, 1.0, psi, x_near_, wpsi_near_);
  psi_integral_ = 0;
  for (double w : wpsi_near_) psi_integral_ += w;
  k0_ = 1 - 2 * psi_integral_;
  if (!std::isfinite(k0_) || k0_ < -1e-14)
    throw std::invalid_argument("radiative_transfer::Dispersion: integral of Psi over [0,1] is " +
                                std::to_string(psi_integral_) + " > 1/2 (no bounded H-function)");
  if (std::fabs(k0_) < 1e-14) k0_ = 0;  // conservative: K(t) ~ t^2 exactly
  x_panel_.resize(kMaxLevels);
  wpsi_panel_.resize(kMaxLevels);
  x_inner_.resize(kMaxLevels + 1);
  wpsi_inner_.resize(kMaxLevels + 1);
  for (int j = 0; j < kMaxLevels; ++j) {
    const double hi = std::ldexp(1.0, -j), lo = std::ldexp(1.0, -(j + 1));
    append_panel(rule, lo, hi, psi, x_panel_[j], wpsi_panel_[j]);
    append_panel(rule, 0.0, hi, psi, x_inner_[j], wpsi_inner_[j]);
  }
  append_panel(rule, 0.0, std::ldexp(1.0, -kMaxLevels), psi, x_inner_[kMaxLevels],
               wpsi_inner_[kMaxLevels]);
}

double Dispersion::operator()(double t) const {
  t = std::fabs(t);
  if (std::isinf(t)) return 1.0;
  const double t2 = t * t;
  if (t <= 1) {
    // K(t) = K(0) + 2 t^2 \int Psi mu^2 / (1 + t^2 mu^2): no cancellation as K -> 0.
    double s = 0;
    for (std::size_t i = 0; i < x_near_.size(); ++i) {
      const double x2 = x_near_[i] * x_near_[i];
      s += wpsi_near_[i] * x2 / (1 + t2 * x2);
    }
    return k0_ + 2 * t2 * s;
  }
  // Pole of the kernel at mu = i/t: panels down to 2^-J <= 2^-8 / t, then [0, 2^-J].
  int levels = static_cast<int>(std::ceil(std::log2(t))) + 8;
  if (levels > kMaxLevels) levels = kMaxLevels;
  double s = 0;
  for (int j = 0; j < levels; ++j) {
    const auto& x = x_panel_[j];
    const auto& w = wpsi_panel_[j];
    for (std::size_t i = 0; i < x.size(); ++i) s += w[i] / (1 + t2 * x[i] * x[i]);
  }
  const auto& x = x_inner_[levels];
  const auto& w = wpsi_inner_[levels];
  for (std::size_t i = 0; i < x.size(); ++i) s += w[i] / (1 + t2 * x[i] * x[i]);
  return 1 - 2 * s;
}

double h_function_from_dispersion(const DispersionFunction& k, double mu) {
  if (!(mu >= 0)) throw std::domain_error("radiative_transfer::h_function: mu must be >= 0");
  if (mu == 0) return 1.0;
  if (std::isinf(mu)) throw std::domain_error("radiative_transfer::h_function: mu is infinite");
  static thread_local const GaussLegendre rule(kThetaPoints);
  const int high = static_cast<int>(std::ceil(std::log2(64.0 / mu)));
  double integral = 0, lo = 0;
  auto add_panel = [&](double a, double b) {
    const double h = 0.5 * (b - a), c = 0.5 * (b + a);
    double s = 0;
    for (int i = 0; i < kThetaPoints; ++i) {
      const double theta = c + h * rule.x[i];
      const double kv = k(std::tan(theta) / mu);
      if (!(kv > 0) || !std::isfinite(kv))
        throw std::domain_error("radiative_transfer::h_function: K(t) <= 0 or not finite at t = " +
                                std::to_string(std::tan(theta) / mu));
      s += rule.w[i] * std::log(kv);
    }
    integral += h * s;
  };
  for (int j = kLowExponent; j <= high; ++j) {
    const double hi = std::atan(mu * std::ldexp(1.0, j));
    if (hi > lo) add_panel(lo, hi);
    lo = hi;
  }
  add_panel(lo, 0.5 * kPi);
  return std::exp(-integral / kPi);
}

double h_function(const Dispersion& k, double mu) {
  return h_function_from_dispersion([&k](double t) { return k(t); }, mu);
}

double h_function(const CharacteristicFunction& characteristic_psi, double mu) {
  const Dispersion k(characteristic_psi);
  return h_function(k, mu);
}

// ---------------------------------------------------------------------------
// HTable

namespace {
constexpr int kTableLevels = 40;
constexpr int kTablePoints = 10;
}  // namespace

void HTable::build_nodes(const CharacteristicFunction& psi) {
  const GaussLegendre rule(kTablePoints);
  auto one = [](double) { return 1.0; };
  for (int j = 0; j < kTableLevels; ++j) {
    const double hi = std::ldexp(1.0, -j), lo = std::ldexp(1.0, -(j + 1));
    append_panel(rule, lo, hi, one, mu_, w_);
  }
  append_panel(rule, 0.0, std::ldexp(1.0, -kTableLevels), one, mu_, w_);
  wpsi_.resize(mu_.size());
  for (std::size_t i = 0; i < mu_.size(); ++i) wpsi_[i] = w_[i] * psi(mu_[i]);
}

HTable::HTable(const CharacteristicFunction& psi) {
  build_nodes(psi);
  const Dispersion k(psi);
  h_.resize(mu_.size());
  wpsih_.resize(mu_.size());
  for (std::size_t i = 0; i < mu_.size(); ++i) {
    h_[i] = h_function(k, mu_[i]);
    wpsih_[i] = wpsi_[i] * h_[i];
  }
}

HTable::HTable(const CharacteristicFunction& psi, const DispersionFunction& k) {
  build_nodes(psi);
  h_.resize(mu_.size());
  wpsih_.resize(mu_.size());
  for (std::size_t i = 0; i < mu_.size(); ++i) {
    h_[i] = h_function_from_dispersion(k, mu_[i]);
    wpsih_[i] = wpsi_[i] * h_[i];
  }
}

double HTable::operator()(double mu) const {
  if (!(mu >= 0)) throw std::domain_error("radiative_transfer::HTable: mu must be >= 0");
  if (mu == 0) return 1.0;
  double s = 0;
  for (std::size_t i = 0; i < mu_.size(); ++i) s += wpsih_[i] / (mu + mu_[i]);
  return 1.0 / (1.0 - mu * s);
}

double HTable::moment(int n) const {
  double s = 0;
  for (std::size_t i = 0; i < mu_.size(); ++i) s += w_[i] * std::pow(mu_[i], n) * h_[i];
  return s;
}

double HTable::psi_weighted_integral() const {
  double s = 0;
  for (double v : wpsih_) s += v;
  return s;
}

}  // namespace mcref::radiative_transfer
