// Derived sphere tables (sim/spheres/derived_tables.h): the Fourier-mode
// estimator recovers the modes of a synthetic binned BRDF with known modes
// exactly (deterministic), and the k_d integration of a known albedo function.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/vec.h"
#include "sim/spheres/derived_tables.h"
#include "sim/tally/brdf_tally.h"

using namespace mcref;

namespace {

double f0(double mi, double mo) { return 0.3 + 0.1 * mi * mo; }
double f1(double mi, double mo) { return -0.05 * std::sqrt((1 - mi * mi) * (1 - mo * mo)); }
double f2(double mi, double mo) { return 0.004 * (1 - mi * mi) * (1 - mo * mo); }
double f3(double, double) { return 0.02; }  // a higher mode, which must not leak into k = 0..2

// Exact cosine-weighted bin average over mu_o in [a, b] of g(mu_i, mu_o).
template <class G>
double mu_average(G g, double mi, double a, double b) {
  const GaussLegendre gl(20);
  double num = 0, den = 0;
  for (std::size_t q = 0; q < gl.x.size(); ++q) {
    const double mu = 0.5 * (a + b) + 0.5 * (b - a) * gl.x[q];
    num += gl.w[q] * mu * g(mi, mu);
    den += gl.w[q] * mu;
  }
  return num / den;
}

}  // namespace

TEST(SpheresModes, WeightsAreExactForLowModes) {
  for (int n : {6, 12, 18}) {
    const Axis phi = Axis::uniform_bins("phi", "rad", 0, kPi, n);
    for (int k = 0; k <= 2; ++k) {
      const std::vector<double> w = fourier_mode_weights(phi, k);
      for (int j = 0; j <= 2 * n - 4; ++j) {
        // Bin averages of cos(j phi), exactly.
        double est = 0;
        for (int b = 0; b < n; ++b) {
          const double a = phi.lower(b), c = phi.upper(b);
          const double avg = j == 0 ? 1.0 : (std::sin(j * c) - std::sin(j * a)) / (j * (c - a));
          est += w[b] * avg;
        }
        EXPECT_NEAR(est, j == k ? 1.0 : 0.0, 1e-12) << "n " << n << " k " << k << " j " << j;
      }
    }
  }
  EXPECT_THROW(fourier_mode_weights(Axis::uniform_bins("phi", "rad", 0, 2 * kPi, 12), 1), std::invalid_argument);
}

TEST(SpheresModes, EstimatorRecoversKnownModes) {
  BrdfLayout l;
  l.theta_o_bins = 5;
  l.phi_bins = 12;
  l.order1_classes = {"sphere"};
  const std::vector<double> theta_i{0.2, 0.9, 1.4}, phi_i{0.0, 0.5};
  const std::vector<Table> tables = make_brdf_tables("brdf", theta_i, phi_i, l);
  const Table& brdf = tables[0];
  ASSERT_EQ(brdf.name, "brdf");
  const Axis& to = brdf.axes[2];
  const Axis& phi = brdf.axes[3];
  // Synthetic bin averages of f0 + f1 cos + f2 cos 2 + f3 cos 3 (channel c scales by c + 1).
  std::vector<double> f(brdf.cells());
  for (std::size_t i = 0; i < theta_i.size(); ++i)
    for (std::size_t p = 0; p < phi_i.size(); ++p)
      for (std::size_t o = 0; o < to.size(); ++o)
        for (std::size_t b = 0; b < phi.size(); ++b)
          for (int c = 0; c < 3; ++c) {
            const double mi = std::cos(theta_i[i]);
            const double a = std::cos(to.upper(o)), e = std::cos(to.lower(o));
            const double lo = phi.lower(b), hi = phi.upper(b);
            double v = mu_average(f0, mi, a, e);
            const double m[4] = {0, mu_average(f1, mi, a, e), mu_average(f2, mi, a, e), mu_average(f3, mi, a, e)};
            for (int k = 1; k <= 3; ++k) v += m[k] * (std::sin(k * hi) - std::sin(k * lo)) / (k * (hi - lo));
            f[brdf.index({i, p, o, b, static_cast<std::size_t>(c)})] = (c + 1) * v;
          }
  const Table modes = make_mode_table(brdf);
  ASSERT_EQ(modes.shape(), (std::vector<std::size_t>{3, 5, 3, 3}));
  const std::vector<double> est = mode_estimate(brdf, f, modes);
  for (std::size_t i = 0; i < theta_i.size(); ++i)
    for (std::size_t o = 0; o < to.size(); ++o)
      for (std::size_t c = 0; c < 3; ++c) {
        const double mi = std::cos(theta_i[i]);
        const double a = std::cos(to.upper(o)), e = std::cos(to.lower(o));
        const double expect[3] = {mu_average(f0, mi, a, e), mu_average(f1, mi, a, e), mu_average(f2, mi, a, e)};
        for (std::size_t k = 0; k < 3; ++k)
          EXPECT_NEAR(est[modes.index({i, o, k, c})], (c + 1.0) * expect[k], 1e-13)
              << "theta_i " << i << " bin " << o << " k " << k;
      }
}

TEST(SpheresModes, SphericalAlbedoOfKnownAlbedo) {
  const int n = 16;
  const GaussLegendre gl(n);
  std::vector<double> theta_i;
  for (int q = n - 1; q >= 0; --q) theta_i.push_back(std::acos(0.5 * (1 + gl.x[q])));  // any order
  const std::vector<double> w = spherical_albedo_weights(theta_i);
  ASSERT_EQ(w.size(), static_cast<std::size_t>(n));
  EXPECT_TRUE(spherical_albedo_weights({0.0, 0.5, 1.0}).empty());
  std::vector<double> shifted = theta_i;
  shifted[3] += 1e-6;
  EXPECT_TRUE(spherical_albedo_weights(shifted).empty());

  BrdfLayout l;
  l.theta_o_bins = 2;
  l.phi_bins = 2;
  l.order1_classes = {"sphere"};
  const std::vector<Table> tables = make_brdf_tables("brdf", theta_i, {0.0}, l);
  const Table* albedo = nullptr;
  for (const Table& t : tables)
    if (t.name == "brdf_albedo") albedo = &t;
  ASSERT_NE(albedo, nullptr);
  const Table kd = make_kd_table(*albedo);
  EXPECT_EQ(kd.name, "brdf_kd");
  // a(mu) = A (1 - B mu^3) + polynomial: 2 \int a mu dmu = A (1 - 2B/5) exactly; the
  // component cells other than the total must be ignored.
  const std::size_t ncomp = albedo->axes[2].size();
  std::vector<double> a(albedo->cells(), 1e9);
  const double A[3] = {0.2, 0.6, 0.95}, B = 0.7;
  for (int i = 0; i < n; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      const double mu = std::cos(theta_i[i]);
      a[albedo->index({static_cast<std::size_t>(i), 0, ncomp - 1, c})] = A[c] * (1 - B * mu * mu * mu);
    }
  const std::vector<double> est = kd_estimate(*albedo, a, w);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(est[c], A[c] * (1 - 2 * B / 5), 1e-14);
  // A non-polynomial albedo (Lambertian-like 1 - sqrt(mu) term): GL16's error is
  // 6.8e-8 here (numpy's leggauss), below the 1e-6 asked.
  for (int i = 0; i < n; ++i) {
    const double mu = std::cos(theta_i[i]);
    a[albedo->index({static_cast<std::size_t>(i), 0, ncomp - 1, 0})] = 1 - 0.5 * std::sqrt(mu);
  }
  EXPECT_NEAR(kd_estimate(*albedo, a, w)[0], 1 - 0.5 * 2 * 2.0 / 5, 1e-6);
}
