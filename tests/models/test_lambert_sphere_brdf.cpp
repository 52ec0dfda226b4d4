// models/lambert_sphere: full BRDF (Eq. 10-12, 21, 41), conventions, and the
// albedo mapping (Eq. 39-40); errors of the published and corrected models
// measured against ReferenceBrdf (no fitted constants).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "models/core/vec.h"
#include "models/lambert_sphere/albedo_mapping.h"
#include "models/lambert_sphere/brdf.h"
#include "models/lambert_sphere/fast_brdf.h"
#include "models/lambert_sphere/fourier_modes.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/reference_brdf.h"
#include "models/lambert_sphere/single_scattering.h"

namespace ls = mcref::lambert_sphere;
using mcref::kPi;
using mcref::Vec3;

namespace {
void record(const std::string& key, double value) {
  testing::Test::RecordProperty(key, std::to_string(value));
  std::printf("[measured] %s = %.6g\n", key.c_str(), value);
}
const double kMu[] = {0.1, 0.3, 0.5, 0.7, 0.9, 1.0};
const double kPhi[] = {0.0, 0.5 * kPi, kPi};
}  // namespace

// phi = phi_o - phi_i, 0 back toward the light (DESIGN.md): vector and scalar
// forms agree, and the back-scattering single scattering peaks at phi = 0.
TEST(lambert_sphere_Brdf, ConventionsAndSingleScattering) {
  const double ti = 0.6, to = 0.9, pi_ = 0.4;
  for (double phi : {0.0, 1.0, -2.0, kPi}) {
    const Vec3 wi = mcref::spherical_direction(ti, pi_), wo = mcref::spherical_direction(to, pi_ + phi);
    EXPECT_NEAR(ls::relative_azimuth(wi, wo), std::remainder(phi, 2 * kPi), 1e-12);
    EXPECT_NEAR(ls::single_scattering(0.8, wi, wo), ls::single_scattering(0.8, wi.z, wo.z, phi), 1e-14);
    EXPECT_NEAR(ls::brdf(0.8, wi, wo), ls::brdf(0.8, wi.z, wo.z, phi), 1e-14);
    EXPECT_NEAR(ls::brdf_fast(0.8, wi, wo), ls::brdf_fast(0.8, wi.z, wo.z, phi), 1e-14);
  }
  EXPECT_GT(ls::single_scattering(1, 0.5, 0.5, 0.0), ls::single_scattering(1, 0.5, 0.5, kPi));
  // Retro-reflection: -omega_i . omega_o = -1, p = 2/(3 pi).
  EXPECT_NEAR(ls::single_scattering(1, 0.5, 0.5, 0.0), 2 / (3 * kPi) / 1.0, 1e-12);
  EXPECT_EQ(ls::single_scattering(1, 0.0, 0.5, 0.0), 0.0);
  EXPECT_EQ(ls::brdf(1, 0.5, -0.1, 0.0), 0.0);
  // The three-term single scattering is the sum of its three modes (192 pi form).
  for (double a : kMu)
    for (double b : kMu)
      for (double phi : kPhi) {
        const double s = std::sqrt((1 - a * a) * (1 - b * b));
        const double f3 = 0.7 * ls::phase_function_three_term(-a * b - s * std::cos(phi)) / (a + b);
        const double sum = ls::single_scattering_zeroth_mode(0.7, a, b) +
                           ls::single_scattering_first_mode(0.7, a, b) * std::cos(phi) +
                           ls::single_scattering_second_mode(0.7, a, b) * std::cos(2 * phi);
        EXPECT_NEAR(sum, f3, 1e-14);
      }
}

TEST(lambert_sphere_Brdf, ReciprocityAndClassMatchesFreeFunction) {
  for (auto v : {ls::FirstModeVariant::published, ls::FirstModeVariant::corrected, ls::FirstModeVariant::fast}) {
    ls::BrdfOptions o;
    o.first_mode = v;
    const ls::Brdf f(0.8, o);
    for (double a : kMu)
      for (double b : kMu)
        for (double phi : kPhi) {
          EXPECT_NEAR(f(a, b, phi), f(b, a, phi), 1e-14);
          EXPECT_NEAR(f(a, b, phi), ls::brdf(0.8, a, b, phi, o), 1e-15);
          EXPECT_NEAR(ls::brdf_fast(0.8, a, b, phi), ls::brdf_fast(0.8, b, a, phi), 1e-14);
          EXPECT_GE(ls::brdf_fast(0.8, a, b, phi), 0.0);
        }
  }
}

// With exact H and exact constants, the corrected model with the second mode
// added equals ReferenceBrdf; published misses half of f_m^(1).
TEST(lambert_sphere_Brdf, CorrectedModelWithExactIngredientsIsTheReference) {
  const double c = 0.9;
  const ls::ReferenceBrdf ref(c, /*include_second_mode=*/false);
  ls::BrdfOptions o;
  o.first_mode = ls::FirstModeVariant::corrected;
  o.h1 = ls::H1Source::exact;
  o.exact_h0 = true;
  o.exact_constants = true;
  const ls::Brdf cor(c, o);
  for (double a : kMu)
    for (double b : kMu)
      for (double phi : kPhi) EXPECT_NEAR(cor(a, b, phi), ref(a, b, phi), 1e-8 * ref(a, b, phi));
}

// Relative error of each model against ReferenceBrdf (with its m = 2 mode) over
// mu_i, mu_o in {0.1, 0.3, 0.5, 0.7, 0.9, 1}, phi in {0, pi/2, pi} and
// c in {0.3, 0.8, 0.95, 0.99}. All asserted bounds are the measured maxima
// rounded up (per-albedo values are recorded). Measured: published 0.338
// (c = 0.3) .. 0.021 (c = 0.99); corrected with the log-separable H^(1) 0.015 ..
// 0.045, worst at mu_i = mu_o = 0.1, phi = pi, where the H^(0) fit (Eq. 31) costs
// ~2 x 0.7 %; with every ingredient exact but f_m^(2) = 0 (Eq. 21): 0.010.
TEST(lambert_sphere_Brdf, ModelErrorsAgainstReference) {
  struct Model {
    const char* name;
    ls::BrdfOptions options;
    double bound;  // measured maximum over the albedos below, rounded up
  };
  ls::BrdfOptions pub, cor_log, cor_pub_h, cor_exact, fast_m1;
  cor_log.first_mode = cor_pub_h.first_mode = cor_exact.first_mode = ls::FirstModeVariant::corrected;
  cor_log.h1 = ls::H1Source::log_separable_fit;
  cor_exact.h1 = ls::H1Source::exact;
  cor_exact.exact_h0 = true;
  cor_exact.exact_constants = true;
  fast_m1.first_mode = ls::FirstModeVariant::fast;
  const std::vector<Model> models = {
      {"published", pub, 0.34},
      {"corrected_eq23_h1", cor_pub_h, 1.05},
      {"corrected_log_separable_h1", cor_log, 0.046},
      {"corrected_exact_no_m2", cor_exact, 0.011},
      {"published_eq29", fast_m1, 0.24},
  };
  std::vector<double> worst(models.size() + 1, 0.0);
  for (double c : {0.3, 0.8, 0.95, 0.99}) {
    const ls::ReferenceBrdf ref(c);
    for (std::size_t k = 0; k < models.size(); ++k) {
      const ls::Brdf f(c, models[k].options);
      double here = 0;
      for (double a : kMu)
        for (double b : kMu)
          for (double phi : kPhi) here = std::fmax(here, std::fabs(f(a, b, phi) / ref(a, b, phi) - 1));
      record(std::string("max_rel_error_") + models[k].name + "_c" + std::to_string(c), here);
      worst[k] = std::fmax(worst[k], here);
    }
    for (double a : kMu)
      for (double b : kMu)
        for (double phi : kPhi)
          worst.back() = std::fmax(worst.back(), std::fabs(ls::brdf_fast(c, a, b, phi) / ref(a, b, phi) - 1));
  }
  for (std::size_t k = 0; k < models.size(); ++k) {
    record(std::string("max_rel_error_") + models[k].name, worst[k]);
    EXPECT_LT(worst[k], models[k].bound) << models[k].name;
  }
  record("max_rel_error_fast_eq41", worst.back());
  EXPECT_LT(worst.back(), 0.21);
}

// Eq. 39-40: near-inverses? Max round-trip errors (measured), Eq. 39 < 0 near
// k_d = 0, and Eq. 40 against the spherical albedo of ReferenceBrdf.
TEST(lambert_sphere_Brdf, AlbedoMapping) {
  const ls::RoundTripError e = ls::albedo_mapping_round_trip_error(100000);
  record("eq39_of_eq40_max_abs_error", e.c_to_kd_to_c);
  record("eq39_of_eq40_worst_c", e.at_c);
  record("eq40_of_eq39_max_abs_error", e.kd_to_c_to_kd);
  record("eq40_of_eq39_worst_kd", e.at_kd);
  EXPECT_LT(e.c_to_kd_to_c, 5.0e-3);   // measured 4.91e-3 at c = 0.963
  EXPECT_LT(e.kd_to_c_to_kd, 3.2e-2);  // measured 3.14e-2 at k_d = 0.869
  EXPECT_NEAR(ls::kd_from_albedo(1.0), 1.0, 1e-15);
  EXPECT_NEAR(ls::albedo_from_kd(1.0), 1.0, 1e-15);
  record("eq39_at_kd0", ls::albedo_from_kd(0.0));
  record("eq40_at_c0", ls::kd_from_albedo(0.0));
  EXPECT_LT(ls::albedo_from_kd(0.0), 0.0);  // Eq. 39 is negative for k_d < 0.0016
  double worst = 0;
  for (double c : {0.1, 0.5, 0.9, 0.99}) {
    const double kd = ls::spherical_albedo_reference(c);
    record("kd_reference_c" + std::to_string(c), kd);
    worst = std::fmax(worst, std::fabs(ls::kd_from_albedo(c) - kd));
  }
  record("eq40_vs_reference_kd_max_abs_error", worst);
  EXPECT_LT(worst, 2.4e-3);  // measured 2.29e-3 at c = 0.99
}
