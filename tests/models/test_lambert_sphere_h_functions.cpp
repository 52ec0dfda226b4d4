// models/lambert_sphere: characteristic functions Psi^(m) (Eq. 13-15), dispersion
// functions K^(m) (Eq. 17-20), exact H^(m) (Eq. 16) and the published fits
// (Eq. 23-25, 31-32), with the fits' errors measured against the exact H.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "models/lambert_sphere/characteristic.h"
#include "models/lambert_sphere/h_functions.h"
#include "models/radiative_transfer/h_function.h"
#include "models/radiative_transfer/isotropic.h"

namespace ls = mcref::lambert_sphere;
namespace rt = mcref::radiative_transfer;

namespace {
void record(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::printf("[measured] %s = %.6g\n", key.c_str(), value);
}
const std::vector<double> kAlbedos = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99};
}  // namespace

// Eq. 13-15 typed as printed against the coefficient form; Eq. 32's K^(0)(0).
TEST(lambert_sphere_HFunctions, CharacteristicFunctionsAsPrinted) {
  for (double c : {0.2, 0.7, 1.0})
    for (double mu : {0.0, 0.3, 0.8, 1.0}) {
      const double m2 = mu * mu;
      const double psi0 = c * (-15 * (c - 1) * (4 * c + 9) * m2 * m2 + (c * (20 * c + 281) - 346) * m2 + 207) / 384;
      const double psi1 = -c * (m2 - 1) * (5 * (4 * c + 9) * m2 - 64) / 192;
      const double psi2 = 15 * c * (m2 - 1) * (m2 - 1) / 256;
      EXPECT_NEAR(ls::characteristic_psi(0, c, mu), psi0, 1e-15);
      EXPECT_NEAR(ls::characteristic_psi(1, c, mu), psi1, 1e-15);
      EXPECT_NEAR(ls::characteristic_psi(2, c, mu), psi2, 1e-15);
    }
  for (double c : {0.2, 0.7, 1.0}) {
    // Eq. 32: 1 - 2 (-c^3/72 + 59 c^2/288 + 89 c/288) = (c-16)(c-1)(4c+9)/144.
    EXPECT_NEAR(ls::dispersion_at_zero(0, c), 1 - 2 * (-c * c * c / 72 + 59 * c * c / 288 + 89 * c / 288), 1e-15);
    for (int m = 0; m < 3; ++m) {
      const rt::Dispersion k(ls::characteristic_polynomial(m, c));
      EXPECT_NEAR(k.at_zero(), ls::dispersion_at_zero(m, c), 1e-14) << "m " << m;
    }
  }
  EXPECT_EQ(ls::dispersion_at_zero(0, 1.0), 0.0);  // conservative
}

// Eq. 18-20 against Eq. 17 by quadrature (rt::Dispersion), relative, for t >= 1/2
// where the printed forms are well conditioned; the series branch below 1/2.
// Measured 2.4e-14; asserted 1e-13. The printed forms alone lose accuracy as
// t -> 0 (bracket ~ t^5): recorded at t = 1e-3.
TEST(lambert_sphere_HFunctions, ClosedFormDispersionMatchesQuadrature) {
  double worst_printed = 0, worst_series = 0;
  for (int m = 0; m < 3; ++m)
    for (double c : {0.1, 0.5, 0.9, 1.0}) {
      const rt::Dispersion k(ls::characteristic_polynomial(m, c));
      for (double e = -6; e <= 6; e += 0.05) {
        const double t = std::pow(10.0, e), ref = k(t);
        worst_series = std::fmax(worst_series, std::fabs(ls::dispersion(m, c, t) - ref) / ref);
        if (t >= 0.5) worst_printed = std::fmax(worst_printed, std::fabs(ls::dispersion_published(m, c, t) - ref) / ref);
      }
    }
  record("K_printed_vs_quadrature_t_ge_0.5", worst_printed);
  record("K_with_series_vs_quadrature", worst_series);
  EXPECT_LT(worst_printed, 1e-13);
  EXPECT_LT(worst_series, 1e-13);
  const double t = 1e-3;
  record("K0_printed_rel_error_c1_t1e-3",
         std::fabs(ls::dispersion_published(0, 1.0, t) / ls::dispersion(0, 1.0, t) - 1));
}

// Exact H through the two routes (closed-form K vs K from Psi by quadrature),
// the isotropic special case, H^(0)(inf) = Eq. 32, and reference values.
TEST(lambert_sphere_HFunctions, ExactHFunctions) {
  for (int m = 0; m < 3; ++m)
    for (double c : {0.3, 0.9, 1.0}) {
      const rt::Dispersion k(ls::characteristic_polynomial(m, c));
      for (double mu : {0.01, 0.5, 1.0})
        EXPECT_NEAR(ls::h_exact(m, c, mu), rt::h_function(k, mu), 1e-12) << "m " << m << " c " << c;
    }
  // Isotropic Psi = c/2 through the same generic machinery is Chandrasekhar's H.
  for (double c : {0.5, 1.0})
    EXPECT_NEAR(rt::h_function([c](double) { return 0.5 * c; }, 0.7), rt::h_isotropic(c, 0.7), 1e-13);
  for (double c : {0.2, 0.8})
    EXPECT_NEAR(ls::h_exact(0, c, 1e9), ls::h0_at_infinity(c), 1e-6 * ls::h0_at_infinity(c));
  record("H0_exact_c1_mu1", ls::h_exact(0, 1.0, 1.0));
  record("H1_exact_c1_mu1", ls::h_exact(1, 1.0, 1.0));
  record("H2_exact_c1_mu1", ls::h_exact(2, 1.0, 1.0));
  EXPECT_NEAR(ls::h_exact(1, 1.0, 1.0), 0.886, 5e-4);  // README: exact H^(1)(1) at c = 1 is 0.886
}

// Published fits against the exact H over mu in [0, 1] (1001 points) and
// c in {0.1, ..., 0.9, 0.95, 0.99}: max relative errors. All bounds asserted
// below are the MEASURED values (rounded up), not the paper's claims, which are
// stated beside them.
TEST(lambert_sphere_HFunctions, FitErrorsAgainstExactH) {
  double e23 = 0, e25 = 0, e31 = 0, elog = 0, e23_mu = 0, e23_c = 0;
  for (double c : kAlbedos) {
    const rt::HTable h0 = ls::h_table(0, c), h1 = ls::h_table(1, c);
    e25 = std::fmax(e25, std::fabs(ls::h1_fit_at_one(c) / h1(1.0) - 1));
    for (int i = 0; i <= 1000; ++i) {
      const double mu = i / 1000.0, x1 = h1(mu), x0 = h0(mu);
      const double r23 = std::fabs(ls::h1_fit(c, mu) / x1 - 1);
      if (r23 > e23) { e23 = r23; e23_mu = mu; e23_c = c; }
      elog = std::fmax(elog, std::fabs(ls::h1_fit_log_separable(c, mu) / x1 - 1));
      e31 = std::fmax(e31, std::fabs(ls::h0_fit(c, mu) / x0 - 1));
    }
  }
  record("H1_eq23_max_rel_error", e23);
  record("H1_eq23_worst_mu", e23_mu);
  record("H1_eq23_worst_c", e23_c);
  record("H1_eq25_max_rel_error", e25);
  record("H1_log_separable_max_rel_error", elog);
  record("H0_eq31_max_rel_error", e31);
  EXPECT_LT(e23, 0.115);    // measured 0.1143 (c = 0.99, mu -> 0: Eq. 23 gives H(1) there, not 1); claimed 0.5 %
  EXPECT_LT(e25, 3.1e-4);   // measured 3.0e-4; claimed 0.5 % (README: 0.05 % at c = 1)
  EXPECT_LT(elog, 3.7e-3);  // measured 3.64e-3: the log-separable reading meets the 0.5 % claim
  EXPECT_LT(e31, 7.1e-3);   // measured 7.07e-3 (c = 0.99, mu ~ 0.05); claimed < 1 %
}

// Eq. 24 on its own: H^(1) at c = 1. Value at mu = 1 is 0.9144 (README: exact 0.886).
TEST(lambert_sphere_HFunctions, Eq24AgainstExactConservativeH1) {
  const rt::HTable h1 = ls::h_table(1, 1.0);
  double worst = 0;
  for (int i = 0; i <= 1000; ++i) {
    const double mu = i / 1000.0;
    worst = std::fmax(worst, std::fabs(ls::h1_fit_conservative(mu) / h1(mu) - 1));
  }
  record("eq24_at_mu1", ls::h1_fit_conservative(1.0));
  record("H1_exact_c1_at_mu1", h1(1.0));
  record("eq24_max_rel_error_vs_exact_c1", worst);
  EXPECT_NEAR(ls::h1_fit_conservative(1.0), std::exp(-0.0894878), 1e-15);
  EXPECT_NEAR(h1(1.0), 0.886133, 1e-6);
  EXPECT_LT(worst, 0.0320);  // measured 0.0319 at mu = 1
  EXPECT_GT(worst, 0.0315);
  // At c = 1 and mu = 1 the printed Eq. 23 gives H(1) x Eq. 24(1) = 0.886 x 0.914:
  record("eq23_at_c1_mu1", ls::h1_fit(1.0, 1.0));
}
