// models/lambert_sphere: Fourier modes of the BRDF (d'Eon 2021, Eq. 22, 28-30, 33-38)
// against (a) the Fourier coefficients of Eq. 10 computed by quadrature over phi
// and (b) the exact three-term half-space (radiative_transfer::ThreeTermHalfSpace).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "models/lambert_sphere/brdf.h"
#include "models/lambert_sphere/fourier_modes.h"
#include "models/lambert_sphere/h_functions.h"
#include "models/lambert_sphere/mode_constants.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/phase_sampling.h"
#include "models/lambert_sphere/reference_brdf.h"

namespace ls = mcref::lambert_sphere;

namespace {
void record(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::printf("[measured] %s = %.6g\n", key.c_str(), value);
}
const double kMu[] = {0.05, 0.3, 0.6, 0.9};
}  // namespace

// 384 pi (Eq. 28) or 192 pi? The cos(phi) coefficient of f1 (Eq. 10) with the
// three-term phase function (Eq. 8), by quadrature over phi, equals the 192 pi
// form to rounding (the integrand is a trigonometric polynomial) and is twice
// Eq. 28's 384 pi term. Zeroth (Eq. 38, 768 pi) and second modes agree.
TEST(lambert_sphere_Fourier, SingleScatteringModesByQuadrature) {
  double worst192 = 0, ratio384 = 0;
  for (double c : {0.3, 1.0})
    for (double a : kMu)
      for (double b : kMu) {
        const double n1 = ls::single_scattering_mode_numeric(c, a, b, 1, ls::PhaseModel::three_term);
        worst192 = std::fmax(worst192, std::fabs(n1 / ls::single_scattering_first_mode(c, a, b) - 1));
        ratio384 = n1 / ls::single_scattering_first_mode_published(c, a, b);
        EXPECT_NEAR(ratio384, 2.0, 1e-12);
        const double n0 = ls::single_scattering_mode_numeric(c, a, b, 0, ls::PhaseModel::three_term);
        EXPECT_NEAR(n0, ls::single_scattering_zeroth_mode(c, a, b), 1e-13 * n0);
        const double n2 = ls::single_scattering_mode_numeric(c, a, b, 2, ls::PhaseModel::three_term);
        EXPECT_NEAR(n2, ls::single_scattering_second_mode(c, a, b), 1e-13 * n0);
        EXPECT_NEAR(ls::single_scattering_mode_numeric(c, a, b, 3, ls::PhaseModel::three_term), 0.0, 1e-13 * n0);
      }
  record("ss_cos_mode_rel_diff_vs_192pi", worst192);
  record("ss_cos_mode_over_384pi_term", ratio384);
  EXPECT_LT(worst192, 1e-12);
  // Exact phase function: its cos(phi) mode differs from the three-term one
  // only through A_4, A_6, ... (recorded at mu_i = mu_o = 0.5).
  record("ss_cos_mode_exact_phase_over_three_term_0.5",
         ls::single_scattering_mode_numeric(1, 0.5, 0.5, 1, ls::PhaseModel::exact) /
             ls::single_scattering_first_mode(1, 0.5, 0.5));
}

// The exact cos(phi) mode of the three-term half-space is 2 x Eq. 22: its
// ratio to c H1 H1 S / (6 pi (mu_i + mu_o)) is exactly scale (1 + q mu_i mu_o +
// l (mu_i + mu_o)) with scale = 2 (least squares; residual ~1e-10).
TEST(lambert_sphere_Fourier, ExactFirstModeIsTwiceEq22) {
  double worst_scale = 0, worst_l = 0, worst_m = 0;
  for (double c : {0.1, 0.5, 0.9, 0.99, 1.0}) {
    const ls::ExactFirstModeConstants k = ls::first_mode_constants_exact(c);
    worst_scale = std::fmax(worst_scale, std::fabs(k.scale - 2));
    const ls::FirstModeConstants fit = ls::first_mode_constants_fit(c);
    worst_l = std::fmax(worst_l, std::fabs(fit.l - k.l));
    worst_m = std::fmax(worst_m, std::fabs(fit.m - k.m));
    // Eq. 22 with exact H and exact l, m reproduces half the exact mode.
    const mcref::radiative_transfer::ThreeTermHalfSpace exact(c, -4.0 / 3.0, 5.0 / 16.0, 1);
    for (double a : kMu)
      for (double b : kMu) {
        const double eq22 = ls::first_mode(c, a, b, ls::h_exact(1, c, a), ls::h_exact(1, c, b), {k.l, k.m});
        EXPECT_NEAR(2 * eq22, exact.mode(a, b), 1e-8 * exact.mode(a, b)) << "c " << c;
      }
  }
  record("first_mode_scale_minus_2_max", worst_scale);
  record("eq26_l_max_abs_error", worst_l);
  record("eq27_m_max_abs_error", worst_m);
  EXPECT_LT(worst_scale, 1e-8);
  EXPECT_LT(worst_l, 1.0e-4);  // measured 8.6e-5 (c = 1)
  EXPECT_LT(worst_m, 1.8e-3);  // measured 1.7e-3 (c = 1)
}

// Eq. 30 is exact in form; A and E (Eq. 33) are exact; B, C, D, F fits (Eq. 34-37)
// deviate most as c -> 1. Exact constants from the three-term solution.
TEST(lambert_sphere_Fourier, ZerothModeConstants) {
  double eb = 0, ec = 0, ed = 0, ef = 0;
  for (double c : {0.1, 0.3, 0.5, 0.7, 0.9, 0.95, 0.99}) {
    const ls::ZerothModeConstants x = ls::zeroth_mode_constants_exact(c), f = ls::zeroth_mode_constants_fit(c);
    EXPECT_NEAR(x.A, f.A, 1e-9) << c;
    EXPECT_NEAR(x.E, f.E, 1e-9) << c;
    eb = std::fmax(eb, std::fabs(x.B - f.B));
    ec = std::fmax(ec, std::fabs(x.C - f.C));
    ed = std::fmax(ed, std::fabs(x.D - f.D));
    ef = std::fmax(ef, std::fabs(x.F - f.F));
    // The polynomial form: exact f^(0) against Eq. 30 with exact H and constants.
    const mcref::radiative_transfer::ThreeTermHalfSpace exact(c, -4.0 / 3.0, 5.0 / 16.0, 0);
    for (double a : {0.02, 0.45, 0.97})
      for (double b : {0.13, 0.71}) {
        const double v = ls::zeroth_mode(a, b, ls::h_exact(0, c, a), ls::h_exact(0, c, b), x);
        EXPECT_NEAR(v, exact.mode(a, b), 1e-9 * v) << c;
      }
  }
  record("eq34_B_max_abs_error", eb);
  record("eq35_C_max_abs_error", ec);
  record("eq36_D_max_abs_error", ed);
  record("eq37_F_max_abs_error", ef);
  EXPECT_LT(eb, 1.3e-3);  // measured 1.27e-3 (c = 0.99)
  EXPECT_LT(ec, 8e-4);    // measured 7.5e-4 (c = 0.99)
  EXPECT_LT(ed, 1e-4);    // measured 8.0e-5
  EXPECT_LT(ef, 4.2e-4);  // measured 4.1e-4 (c = 0.99)
}

// Consequences for f_m^(1) with exact ingredients: `published` is exactly half the
// true multiple-scattering mode, `corrected` equals it, `subtract_192` is off by
// O(c) (it leaves -c S (45 mu mu + 64) / (384 pi (mu_i + mu_o)) at c -> 0).
// Eq. 29 is recorded against the exact mode.
TEST(lambert_sphere_Fourier, MultipleScatteringFirstModeVariants) {
  double fast_lo = 1e9, fast_hi = -1e9;
  for (double c : {0.3, 0.9}) {
    const ls::ReferenceBrdf ref(c);
    auto build = [c](ls::FirstModeVariant v) {
      ls::BrdfOptions o;
      o.first_mode = v;
      o.h1 = ls::H1Source::exact;
      o.exact_constants = true;
      return ls::Brdf(c, o);
    };
    const ls::Brdf pub = build(ls::FirstModeVariant::published), cor = build(ls::FirstModeVariant::corrected);
    for (double a : kMu)
      for (double b : kMu) {
        const double truth = ref.multiple_mode(1, a, b);
        EXPECT_NEAR(pub.multiple_first_mode(a, b), 0.5 * truth, 1e-8 * std::fabs(truth));
        EXPECT_NEAR(cor.multiple_first_mode(a, b), truth, 1e-8 * std::fabs(truth));
        const double r = ls::multiple_first_mode_fast(c, a, b) / truth;
        fast_lo = std::fmin(fast_lo, r);
        fast_hi = std::fmax(fast_hi, r);
      }
  }
  record("eq29_over_exact_fm1_min", fast_lo);
  record("eq29_over_exact_fm1_max", fast_hi);
  EXPECT_GT(fast_lo, 0.37);  // measured 0.375-0.435 here: Eq. 29 is ~0.8 x (exact / 2)
  EXPECT_LT(fast_hi, 0.44);
  // O(c) residue of subtract_192 at small c (exact H^(1); relative O(c) = 1e-4).
  const double c = 1e-4, a = 0.4, b = 0.7;
  const double eq22 = ls::first_mode(c, a, b, ls::h_exact(1, c, a), ls::h_exact(1, c, b), ls::first_mode_constants_fit(c));
  EXPECT_NEAR(ls::multiple_first_mode_from(eq22, c, a, b, ls::FirstModeVariant::subtract_192) /
                  -ls::single_scattering_first_mode_published(c, a, b),
              1.0, 1e-3);
  EXPECT_NEAR(ls::multiple_first_mode_from(eq22, c, a, b, ls::FirstModeVariant::published) /
                  ls::single_scattering_first_mode_published(c, a, b),
              0.0, 1e-3);
}

namespace {

// Multiple-scattering (order >= 2) Fourier modes m = 0, 1, 2 at (mu_i, mu_o) of
// the half-space (extinction 1, albedo c) by an analog volumetric Monte Carlo
// with next-event estimation from 32 azimuths per collision (trapezoid rule,
// exact for the periodic integrand to far below the noise). exact_phase: Eq. 1
// sampled by Eq. 5; otherwise the three-term p_3 of the reference, directions
// from an even mixture of the sphere and Eq. 1, weighted by p_3 over their
// density (signed: p_3 < 0 near mu = 1).
struct ModeEstimate {
  double mean[3], se[3];
};
ModeEstimate monte_carlo_modes(double c, double mui, double muo, long photons, bool exact_phase, std::uint64_t seed) {
  using mcref::Vec3;
  const double pi = mcref::kPi;
  const int k_phi = 32;
  auto phase = [&](double mu) { return exact_phase ? ls::phase_function(mu) : ls::phase_function_three_term(mu); };
  const Vec3 wi{std::sqrt(1 - mui * mui), 0, mui};
  std::vector<Vec3> wo(k_phi);
  for (int k = 0; k < k_phi; ++k) {
    const double phi = 2 * pi * (k + 0.5) / k_phi;  // phi_i = 0, so phi = phi_o (0: toward the light)
    wo[k] = {std::sqrt(1 - muo * muo) * std::cos(phi), std::sqrt(1 - muo * muo) * std::sin(phi), muo};
  }
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  mcref::Rng rng(seed);
  for (long n = 0; n < photons; ++n) {
    Vec3 d = -wi;  // propagation
    double z = 0, w = 1, score[3] = {0, 0, 0};
    for (int order = 1;; ++order) {
      z += -std::log1p(-rng.uniform()) * d.z;
      if (z > 0) break;
      if (order >= 2) {
        const double att = std::exp(z / muo) / muo;  // exp(-depth / mu_o) / mu_o
        for (int k = 0; k < k_phi; ++k) {
          const double phi = 2 * pi * (k + 0.5) / k_phi;
          const double v = w * c * phase(mcref::dot(d, wo[k])) * att / k_phi;
          score[0] += v;
          score[1] += 2 * v * std::cos(phi);
          score[2] += 2 * v * std::cos(2 * phi);
        }
      }
      double mu;
      if (exact_phase) {
        w *= c;
        mu = ls::sample_phase_cosine_exact(rng.uniform(), rng.uniform(), rng.uniform());
      } else {  // half uniform, half Eq. 1: a density > 0 wherever p_3 is not 0 (Eq. 1 is 0 at mu = 1)
        const double u = rng.uniform(), a = rng.uniform(), b = rng.uniform(), e = rng.uniform();
        mu = u < 0.5 ? 2 * a - 1 : ls::sample_phase_cosine_exact(a, b, e);
        w *= c * phase(mu) / (0.5 / (4 * pi) + 0.5 * ls::phase_function(mu));
      }
      if (std::fabs(w) < 1e-3) {  // Russian roulette
        if (rng.uniform() < 0.5) break;
        w *= 2;
      }
      d = ls::scattered_direction(d, mu, rng.uniform());
    }
    for (int m = 0; m < 3; ++m) {
      sum[m] += score[m];
      sum2[m] += score[m] * score[m];
    }
  }
  ModeEstimate e;
  for (int m = 0; m < 3; ++m) {
    e.mean[m] = sum[m] / photons;
    e.se[m] = std::sqrt((sum2[m] / photons - e.mean[m] * e.mean[m]) / photons);
  }
  return e;
}

}  // namespace

// The reference three-term half-space (ReferenceBrdf, what decides the factor
// 2 of Eq. 22) against an independent Monte Carlo of the same three-term
// medium, c = 0.8, mu_i = 0.6, mu_o = 0.5: seed {2021, 23}, 4 10^5 photons,
// stderr from the photon scores; each mode within 3.6 stderr (two-sided normal
// quantile at 1 - (1 - 1e-3)^(1/3), Sidak over the 3 modes). The published
// f_m^(1) (half of it) must be rejected (> 20 stderr). The same Monte Carlo
// with the exact phase function Eq. 1 is recorded beside it: the three-term
// truncation, measured, not judged.
TEST(lambert_sphere_Fourier, IndependentMonteCarloDecidesTheFactorTwo) {
  const double c = 0.8, mui = 0.6, muo = 0.5;
  const ModeEstimate mc = monte_carlo_modes(c, mui, muo, 400000, false, mcref::stream_seed({2021, 23}));
  const ModeEstimate exact = monte_carlo_modes(c, mui, muo, 200000, true, mcref::stream_seed({2021, 22}));
  const ls::ReferenceBrdf ref(c);
  ls::BrdfOptions options;
  options.h1 = ls::H1Source::exact;
  options.exact_h0 = true;
  options.exact_constants = true;
  const ls::Brdf published(c, options);  // first_mode = published
  for (int m = 0; m < 3; ++m) {
    const double r = ref.multiple_mode(m, mui, muo);
    const std::string k = std::to_string(m);
    record("mc_three_term_fm" + k, mc.mean[m]);
    record("mc_three_term_fm" + k + "_stderr", mc.se[m]);
    record("mc_exact_phase_fm" + k, exact.mean[m]);
    record("mc_exact_phase_fm" + k + "_stderr", exact.se[m]);
    record("reference_fm" + k, r);
    record("truncation_fm" + k + "_relative", (exact.mean[m] - r) / r);
    EXPECT_NEAR(mc.mean[m], r, 3.6 * mc.se[m]) << "m " << m;
    // The resolution asked of the test: 10 % of f^(0) and f^(1), 25 % of the small f^(2) (0.4 % of f^(0)).
    EXPECT_LT(3.6 * mc.se[m], (m < 2 ? 0.1 : 0.25) * std::fabs(r)) << "m " << m;
  }
  const double pub = published.multiple_first_mode(mui, muo);
  record("published_fm1", pub);
  record("mc_minus_published_fm1_in_stderr", (mc.mean[1] - pub) / mc.se[1]);
  EXPECT_GT(std::fabs(mc.mean[1] - pub), 20 * mc.se[1]);
  EXPECT_LT(mc.mean[1], 0.0);  // f_m^(1) < 0 with phi = 0 toward the light: multiple scattering leans to the mirror side
}
