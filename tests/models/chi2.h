#pragma once
// Chi-square goodness-of-fit test for direction samplers, after Mitsuba 3's
// chi2.py: equal-area bins in (cos theta, phi), the pdf integrated over each
// cell by Gauss–Legendre quadrature, cells with a small expected count pooled,
// p-value from the regularised upper incomplete gamma function, Šidák
// correction for several tests in one file, and a dump of the worst cells on
// failure. Header-only, for tests/models/test_*.cpp.
#include <algorithm>
#include <cmath>

#include "models/core/statistics.h"
#include <cstdint>
#include <numeric>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/rng.h"
#include "models/core/vec.h"

namespace mcref::test {

// The incomplete gamma and chi-squared survival live in models/core/statistics.h.
using mcref::regularized_gamma_p;
using mcref::regularized_gamma_q;
inline double chi2_survival(double statistic, int dof) { return mcref::chi2_survival(statistic, dof); }

// Šidák-corrected per-test significance for `tests` independent tests at
// family-wise level `alpha`.
inline double sidak_alpha(double alpha, int tests) { return 1 - std::pow(1 - alpha, 1.0 / tests); }

struct Chi2Options {
  int theta_bins = 32;        // equal steps in cos theta
  int phi_bins = 64;          // equal steps in phi over [0, 2 pi)
  bool hemisphere = true;     // cos theta in [0, 1]; otherwise [-1, 1]
  int quad_points = 8;        // Gauss–Legendre points per cell and axis
  int quad_subdivisions = 2;  // sub-cells per cell and axis
  double min_expected = 5;    // cells below this expected count are pooled
};

struct Chi2Result {
  double statistic = 0;
  int dof = 0;
  double p_value = 0;
  int cells = 0;              // cells entering the statistic (pool counted once)
  int pooled_cells = 0;       // cells merged into the pool
  double expected_total = 0;  // sum of expected counts (≈ samples if the pdf integrates to 1)
  std::uint64_t samples = 0;
  std::uint64_t invalid = 0;  // samples outside the domain or non-finite
  std::string report;         // summary, plus the worst cells
  bool passed(double alpha) const { return invalid == 0 && p_value > alpha; }
};

// Runs the test. `sample(u1, u2)` (or `sample(u1, u2, u3)`) returns a unit
// Vec3; `pdf(w)` is its density per unit solid angle. Uniforms come from
// mcref::Rng(seed).
template <class Sampler, class Pdf>
Chi2Result chi2_test(Sampler&& sample, Pdf&& pdf, std::uint64_t samples, std::uint64_t seed,
                     const Chi2Options& opt = Chi2Options()) {
  const int nt = opt.theta_bins, np = opt.phi_bins, cells = nt * np;
  const double z_lo = opt.hemisphere ? 0.0 : -1.0, dz = (1 - z_lo) / nt, dphi = 2 * kPi / np;
  auto cell_of = [&](int it, int ip) { return it * np + ip; };

  Chi2Result r;
  r.samples = samples;
  std::vector<double> observed(cells, 0.0), expected(cells, 0.0);
  Rng rng(seed);
  for (std::uint64_t k = 0; k < samples; ++k) {
    Vec3 w;
    const double u1 = rng.uniform(), u2 = rng.uniform();
    if constexpr (std::is_invocable_v<Sampler, double, double, double>) w = sample(u1, u2, rng.uniform());
    else w = sample(u1, u2);
    if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) || w.z < z_lo ||
        std::fabs(length(w) - 1) > 1e-6) {
      ++r.invalid;
      continue;
    }
    const int it = std::min(nt - 1, static_cast<int>((1 - w.z) / dz));  // bin 0 at the pole
    const int ip = std::min(np - 1, static_cast<int>(spherical_phi(w) / dphi));
    observed[cell_of(it, ip)] += 1;
  }

  const GaussLegendre rule(opt.quad_points);
  const int sub = opt.quad_subdivisions;
  for (int it = 0; it < nt; ++it) {
    const double z1 = 1 - it * dz;  // cell spans z in [z1 - dz, z1]
    for (int ip = 0; ip < np; ++ip) {
      double integral = 0;
      for (int a = 0; a < sub; ++a) {
        for (int b = 0; b < sub; ++b) {
          const double za = z1 - dz + a * dz / sub, pa = ip * dphi + b * dphi / sub;
          integral += rule.integrate(
              [&](double z) {
                return rule.integrate(
                    [&](double phi) {
                      const double s = std::sqrt(std::max(0.0, 1 - z * z));
                      return pdf(Vec3{s * std::cos(phi), s * std::sin(phi), z});
                    },
                    pa, pa + dphi / sub);
              },
              za, za + dz / sub);
        }
      }
      expected[cell_of(it, ip)] = integral * static_cast<double>(samples);
    }
  }
  r.expected_total = std::accumulate(expected.begin(), expected.end(), 0.0);

  // Pool low cells (sorted by expected count), Mitsuba-style.
  std::vector<int> order(cells);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pool_obs = 0, pool_exp = 0, stat = 0;
  int dof = 0;
  bool impossible = false;
  for (int c : order) {
    if (expected[c] <= 0) {
      if (observed[c] > 0) impossible = true;  // samples where the pdf is zero
      continue;
    }
    if (expected[c] < opt.min_expected || (pool_exp > 0 && pool_exp < opt.min_expected)) {
      pool_obs += observed[c];
      pool_exp += expected[c];
      ++r.pooled_cells;
    } else {
      const double d = observed[c] - expected[c];
      stat += d * d / expected[c];
      ++dof;
    }
  }
  if (pool_exp > 0) {
    const double d = pool_obs - pool_exp;
    stat += d * d / pool_exp;
    ++dof;
  }
  r.cells = dof;
  r.dof = dof - 1;
  r.statistic = stat;
  r.p_value = (impossible || r.dof < 1) ? 0.0 : chi2_survival(stat, r.dof);

  std::ostringstream os;
  os << "chi2 = " << stat << ", dof = " << r.dof << ", p = " << r.p_value << ", pooled "
     << r.pooled_cells << " cells, expected total " << r.expected_total << " of " << samples
     << ", invalid samples " << r.invalid << (impossible ? ", samples in zero-pdf cells" : "");
  // The five cells contributing most to the statistic.
  std::vector<int> worst(cells);
  std::iota(worst.begin(), worst.end(), 0);
  auto contrib = [&](int c) {
    return expected[c] > 0 ? (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c]
                           : observed[c];
  };
  std::partial_sort(worst.begin(), worst.begin() + std::min(5, cells), worst.end(),
                    [&](int a, int b) { return contrib(a) > contrib(b); });
  for (int k = 0; k < std::min(5, cells); ++k) {
    const int c = worst[k];
    os << "\n  cell (cos theta bin " << c / np << ", phi bin " << c % np << "): observed "
       << observed[c] << ", expected " << expected[c];
  }
  r.report = os.str();
  return r;
}

}  // namespace mcref::test
