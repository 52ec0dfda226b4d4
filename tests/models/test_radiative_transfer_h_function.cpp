// models/radiative_transfer: H-functions by Fock's integral (d'Eon 2021 Eq. 16-17),
// checked against Chandrasekhar's table, exact moment identities and an
// independent solution of the H-equation by iteration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "models/core/quadrature.h"
#include "models/radiative_transfer/h_function.h"
#include "models/radiative_transfer/isotropic.h"

namespace rt = mcref::radiative_transfer;

namespace {

void record(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::printf("[measured] %s = %.6g\n", key.c_str(), value);
}

// Composite Gauss nodes on [0, 1], panels graded toward 0, 12 points each (a
// different set from HTable's, so the iteration below is independent of it).
struct Nodes {
  std::vector<double> x, w;
  Nodes() {
    const mcref::GaussLegendre rule(12);
    auto panel = [&](double a, double b) {
      for (std::size_t i = 0; i < rule.x.size(); ++i) {
        x.push_back(0.5 * (a + b) + 0.5 * (b - a) * rule.x[i]);
        w.push_back(0.5 * (b - a) * rule.w[i]);
      }
    };
    panel(0.0, std::ldexp(1.0, -30));
    for (int j = 29; j >= 0; --j) panel(std::ldexp(1.0, -(j + 1)), std::ldexp(1.0, -j));
  }
};

// Solves the discretised H-equation on the nodes: a few hundred sweeps of the
// classic iteration H = 1 / (1 - mu \int Psi H / (mu + mu')), then Newton's
// method (dense LU) on
//   classic form:      F_i = H_i (1 - mu_i \sum_k w_k Psi_k H_k / (mu_i + mu_k)) - 1, or
//   Chandrasekhar's alternative form (conservative case, where the classic form's
//   Jacobian is singular at the solution):
//                      F_i = H_i \sum_k w_k Psi_k mu_k H_k / (mu_i + mu_k) - 1.
std::vector<double> solve_h_equation(const Nodes& n, const rt::CharacteristicFunction& psi, bool alternative,
                                     int* newton_steps) {
  const std::size_t m = n.x.size();
  std::vector<double> wpsi(m), h(m, 1.0), s(m);
  for (std::size_t k = 0; k < m; ++k) wpsi[k] = n.w[k] * psi(n.x[k]);
  auto sums = [&]() {
    for (std::size_t i = 0; i < m; ++i) {
      double acc = 0;
      for (std::size_t k = 0; k < m; ++k) acc += wpsi[k] * h[k] / (n.x[i] + n.x[k]);
      s[i] = acc;
    }
  };
  for (int it = 0; it < 300; ++it) {
    sums();
    for (std::size_t i = 0; i < m; ++i) h[i] = 1 / (1 - n.x[i] * s[i]);
  }
  std::vector<double> jac(m * m), f(m);
  for (int step = 1; step <= 50; ++step) {
    for (std::size_t i = 0; i < m; ++i) {
      double acc = 0;
      for (std::size_t k = 0; k < m; ++k) acc += wpsi[k] * h[k] * (alternative ? n.x[k] : 1.0) / (n.x[i] + n.x[k]);
      s[i] = acc;
    }
    for (std::size_t i = 0; i < m; ++i) {
      if (alternative) {
        f[i] = h[i] * s[i] - 1;
        for (std::size_t k = 0; k < m; ++k)
          jac[i * m + k] = h[i] * wpsi[k] * n.x[k] / (n.x[i] + n.x[k]) + (i == k ? s[i] : 0.0);
      } else {
        f[i] = h[i] * (1 - n.x[i] * s[i]) - 1;
        for (std::size_t k = 0; k < m; ++k)
          jac[i * m + k] = -h[i] * n.x[i] * wpsi[k] / (n.x[i] + n.x[k]) + (i == k ? 1 - n.x[i] * s[i] : 0.0);
      }
    }
    // Solve jac * dh = f by Gaussian elimination with partial pivoting.
    for (std::size_t col = 0; col < m; ++col) {
      std::size_t piv = col;
      for (std::size_t r = col + 1; r < m; ++r)
        if (std::fabs(jac[r * m + col]) > std::fabs(jac[piv * m + col])) piv = r;
      if (piv != col) {
        for (std::size_t q = 0; q < m; ++q) std::swap(jac[col * m + q], jac[piv * m + q]);
        std::swap(f[col], f[piv]);
      }
      for (std::size_t r = col + 1; r < m; ++r) {
        const double g = jac[r * m + col] / jac[col * m + col];
        if (g == 0) continue;
        for (std::size_t q = col; q < m; ++q) jac[r * m + q] -= g * jac[col * m + q];
        f[r] -= g * f[col];
      }
    }
    double change = 0;
    for (std::size_t col = m; col-- > 0;) {
      double acc = f[col];
      for (std::size_t q = col + 1; q < m; ++q) acc -= jac[col * m + q] * f[q];
      f[col] = acc / jac[col * m + col];
      h[col] -= f[col];
      change = std::fmax(change, std::fabs(f[col]));
    }
    if (change < 1e-14) {
      *newton_steps = step;
      return h;
    }
  }
  *newton_steps = -1;
  return h;
}

}  // namespace

// Chandrasekhar (1960), Table for conservative isotropic scattering: H(1) = 2.90781
// (5 decimals: half a unit of the last digit is 5e-6).
TEST(radiative_transfer_HFunction, ConservativeIsotropicMatchesChandrasekharTable) {
  EXPECT_NEAR(rt::h_isotropic(1.0, 1.0), 2.90781, 5e-6);
  EXPECT_NEAR(rt::h_function([](double) { return 0.5; }, 1.0), 2.90781, 5e-6);
  record("H_iso_w1_mu1", rt::h_isotropic(1.0, 1.0));
  // The brief quoted H(0.5) = 2.0138; both methods here (and the iteration test
  // below) give 2.012779, Chandrasekhar's 2.01278, so 2.0138 is not used.
  record("H_iso_w1_mu0.5", rt::h_isotropic(1.0, 0.5));
  EXPECT_NEAR(rt::h_isotropic(1.0, 0.5), 2.01278, 5e-6);
}

// Exact identities: alpha_0 = \int H = 2 and alpha_1 = \int mu H = 2/sqrt(3) for
// conservative isotropic scattering (Chandrasekhar 1960, Sec. 39), and for any Psi
// \int Psi H = 1 - sqrt(1 - 2 \int Psi). Quadrature of the table: 1e-12.
TEST(radiative_transfer_HFunction, MomentIdentities) {
  const rt::HTable h = rt::isotropic_h_table(1.0);
  EXPECT_NEAR(h.moment(0), 2.0, 1e-12);
  EXPECT_NEAR(h.moment(1), 2.0 / std::sqrt(3.0), 1e-12);
  struct Case {
    const char* name;
    rt::CharacteristicFunction psi;
    double integral;
  };
  const std::vector<Case> cases = {
      {"iso 0.1", [](double) { return 0.05; }, 0.05},
      {"iso 0.9", [](double) { return 0.45; }, 0.45},
      {"iso 0.999", [](double) { return 0.4995; }, 0.4995},
      {"Rayleigh conservative", [](double mu) { return 3.0 / 16.0 * (3 - mu * mu); }, 0.5},
      {"negative", [](double mu) { return -0.3 * (1 - mu * mu); }, -0.2},
  };
  for (const auto& c : cases) {
    const rt::HTable t(c.psi);
    EXPECT_NEAR(t.psi_weighted_integral(), 1 - std::sqrt(1 - 2 * c.integral), 1e-12) << c.name;
  }
}

// Independent check: the discretised H-equation solved on other nodes
// (iteration + Newton), compared with Fock's integral at those nodes. The
// solution's own error is the quadrature error of the graded 12-point panels,
// ~1e-13 here. Measured worst 2.2e-13 (Rayleigh, conservative); asserted 1e-11.
TEST(radiative_transfer_HFunction, FockAgreesWithSolutionOfTheHEquation) {
  const Nodes nodes;
  struct Case {
    const char* name;
    rt::CharacteristicFunction psi;
    bool conservative;
  };
  const std::vector<Case> cases = {
      {"iso 0.5", [](double) { return 0.25; }, false},
      {"iso 0.9", [](double) { return 0.45; }, false},
      {"iso 0.99", [](double) { return 0.495; }, false},
      {"iso 1", [](double) { return 0.5; }, true},
      {"Rayleigh 1", [](double mu) { return 3.0 / 16.0 * (3 - mu * mu); }, true},
      {"negative", [](double mu) { return -0.3 * (1 - mu * mu); }, false},
  };
  for (const auto& c : cases) {
    int steps = 0;
    const std::vector<double> h = solve_h_equation(nodes, c.psi, c.conservative, &steps);
    ASSERT_GT(steps, 0) << c.name;
    const rt::Dispersion k(c.psi);
    double worst = 0;
    for (std::size_t i = 0; i < nodes.x.size(); i += 3)
      worst = std::fmax(worst, std::fabs(rt::h_function(k, nodes.x[i]) - h[i]));
    record(std::string("fock_vs_h_equation_") + c.name, worst);
    EXPECT_LT(worst, 1e-11) << c.name << " after " << steps << " Newton steps";
  }
}

// K from Psi by quadrature against the closed form 1 - w atan(t)/t (relative).
TEST(radiative_transfer_HFunction, DispersionQuadratureMatchesClosedForm) {
  for (double w : {0.3, 0.9, 1.0}) {
    const rt::Dispersion k([w](double) { return 0.5 * w; });
    EXPECT_NEAR(k.at_zero(), 1 - w, 1e-14);  // rounding of a 24-term sum
    double worst = 0;
    for (double e = -8; e <= 12; e += 0.1) {
      const double t = std::pow(10.0, e), exact = rt::isotropic_dispersion(w, t);
      worst = std::fmax(worst, std::fabs(k(t) - exact) / exact);
    }
    EXPECT_LT(worst, 1e-13) << "albedo " << w;
  }
}

// The table's Nystrom interpolation against direct Fock evaluation, including
// tiny mu (H ~ 1 + mu log mu) and mu > 1 (relative: H(8) ~ 15 at albedo 1).
// Measured max relative error ~1e-13; asserted 1e-12.
TEST(radiative_transfer_HFunction, TableInterpolationAccuracy) {
  double worst = 0;
  for (double w : {0.2, 0.9, 1.0}) {
    const rt::HTable t([w](double) { return 0.5 * w; });
    for (int i = 0; i <= 400; ++i) {
      const double mu = i == 0 ? 1e-12 : std::pow(i / 200.0, 3);  // up to 8
      const double exact = rt::h_isotropic(w, mu);
      worst = std::fmax(worst, std::fabs(t(mu) - exact) / exact);
    }
  }
  record("htable_max_rel_error", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(radiative_transfer_HFunction, LimitsAndErrors) {
  EXPECT_EQ(rt::h_isotropic(0.7, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(rt::h_isotropic(0.0, 0.6), 1.0);
  // H(inf) = 1/sqrt(K(0)) for the non-conservative case.
  EXPECT_NEAR(rt::h_isotropic(0.5, 1e8), 1 / std::sqrt(0.5), 1e-7);
  EXPECT_THROW(rt::Dispersion([](double) { return 0.6; }), std::invalid_argument);
  EXPECT_THROW(rt::h_isotropic(0.5, -0.1), std::domain_error);
}
