#pragma once
// Chandrasekhar H-functions of a semi-infinite medium, from a characteristic
// function Psi, by Fock's integral (d'Eon 2021, Eq. 16-17).
//
//   H(mu) = 1 + mu H(mu) \int_0^1 Psi(mu') H(mu') / (mu + mu') dmu'      (H-equation)
//
// Psi is any smooth function on [0, 1] (usually an even polynomial) with
// \int_0^1 Psi <= 1/2 (equality: the conservative case). Psi may be negative in
// places (d'Eon's Psi^(1) is), as long as the dispersion function K below stays
// positive on t >= 0.
//
// Dispersion (characteristic) function, d'Eon Eq. 17 with s = 1/mu:
//   K(t) = 1 - 2 \int_0^1 Psi(mu) / (1 + t^2 mu^2) dmu,   K(0) = 1 - 2 \int_0^1 Psi.
// Fock's formula, d'Eon Eq. 16, substituted t = tan(theta) / mu:
//   H(mu) = exp(-(mu/pi) \int_0^inf log K(t) / (1 + mu^2 t^2) dt)
//         = exp(-(1/pi) \int_0^{pi/2} log K(tan(theta) / mu) d theta).
// The theta integral is done by 16-point Gauss-Legendre on panels whose ends are
// theta_j = atan(mu 2^j), i.e. geometric in t from 2^-52 to 2^6/mu: this resolves
// the log singularity of the conservative case (K ~ t^2 at t -> 0) and the
// near-singular kernel of small mu. Measured accuracy (tests): |dH| < 1e-12.
#include <functional>
#include <vector>

namespace mcref::radiative_transfer {

// Psi(mu), mu in [0, 1].
using CharacteristicFunction = std::function<double(double)>;
// K(t), t >= 0.
using DispersionFunction = std::function<double(double)>;

// K(t) computed from Psi by quadrature (Eq. 17). Psi is sampled once, at fixed
// nodes (composite Gauss-Legendre, panels graded geometrically toward mu = 0 so
// that the near pole of 1/(1 + t^2 mu^2) at mu = i/t is resolved for large t);
// each K(t) then costs O(log2 t + 10) x 12 multiply-adds. Relative accuracy ~1e-15
// for polynomial Psi. For t <= 1 it uses K(0) + 2 t^2 \int Psi mu^2 / (1 + t^2 mu^2),
// free of cancellation as K -> 0.
class Dispersion {
 public:
  // Throws std::invalid_argument if \int_0^1 Psi > 1/2 (beyond rounding).
  explicit Dispersion(const CharacteristicFunction& psi);
  double operator()(double t) const;
  // K(0) = 1 - 2 \int_0^1 Psi; set to exactly 0 when |K(0)| < 1e-14 (conservative).
  double at_zero() const { return k0_; }
  // \int_0^1 Psi(mu) dmu.
  double psi_integral() const { return psi_integral_; }

 private:
  static constexpr int kMaxLevels = 64;
  double k0_ = 1, psi_integral_ = 0;
  // Nodes/weights on [0, 1/2] and [1/2, 1] (t <= 1); then per level j the panel
  // [2^-(j+1), 2^-j] and the innermost panel [0, 2^-j] (t > 1).
  std::vector<double> x_near_, wpsi_near_;
  std::vector<std::vector<double>> x_panel_, wpsi_panel_, x_inner_, wpsi_inner_;
};

// H(mu) by Fock's integral from a dispersion function K (Eq. 16). K must be
// positive on (0, inf), accurate in relative terms near t = 0 (where it may
// vanish like t^2), and tend to 1 as t -> inf. mu >= 0; H(0) = 1.
// Throws std::domain_error if K(t) <= 0 or is not finite at a node.
double h_function_from_dispersion(const DispersionFunction& k, double mu);

// H(mu) from a characteristic function Psi (builds a Dispersion, then Eq. 16).
// Cost ~0.2 ms; for many evaluations with the same Psi use HTable.
double h_function(const CharacteristicFunction& characteristic_psi, double mu);
// Same, reusing a Dispersion built once.
double h_function(const Dispersion& k, double mu);

// H tabulated once per Psi, evaluated anywhere in mu >= 0 by the Nystrom
// interpolation of the H-equation itself:
//   H(mu) = 1 / (1 - mu \sum_k w_k Psi(mu_k) H(mu_k) / (mu + mu_k)),
// with H(mu_k) from Fock's integral at composite Gauss nodes mu_k (10 points per
// panel [2^-(j+1), 2^-j], j < 40, plus [0, 2^-40]; 410 nodes). The grading keeps
// the near singularity at mu' = -mu resolved for small mu, and the formula keeps
// H's mu log mu behaviour at 0 that polynomial interpolation would miss.
// Build 0.05-0.1 s; evaluation ~0.5 us; measured |H_table / H_Fock - 1| < 1e-13
// for mu in [0, 8] (tests).
class HTable {
 public:
  explicit HTable(const CharacteristicFunction& psi);
  // Node values from a given (e.g. closed-form, faster) dispersion function k
  // that must equal K of psi (Eq. 17).
  HTable(const CharacteristicFunction& psi, const DispersionFunction& k);
  double operator()(double mu) const;
  // Moment alpha_n = \int_0^1 mu^n H(mu) dmu, by the table's quadrature.
  double moment(int n) const;
  // \int_0^1 Psi(mu) H(mu) dmu; equals 1 - sqrt(1 - 2 \int Psi) (exact identity).
  double psi_weighted_integral() const;
  const std::vector<double>& nodes() const { return mu_; }
  const std::vector<double>& node_values() const { return h_; }

 private:
  void build_nodes(const CharacteristicFunction& psi);
  std::vector<double> mu_, w_, wpsi_, h_, wpsih_;
};

}  // namespace mcref::radiative_transfer
