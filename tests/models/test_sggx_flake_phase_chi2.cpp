// Chi-square goodness of fit of the specular SGGX flake phase sampler
// (visible normal + reflection) against f_p = D(h)/(4 sigma(wi)) (SpongeCake
// Eq. 4): 10^6 samples per case, 64 x 128 equal-area (cos, phi) bins around
// -wi (where h is undefined), cells below 5 expected pooled, level 0.01
// Sidak-corrected over the cases of this file, fixed seeds.
#include <gtest/gtest.h>

#include <cstdio>

#include "models/sggx/flake_phase.h"
#include "tests/models/sggx_chi2.h"
#include "tests/models/sggx_chi2_cases.h"

namespace {

namespace sg = mcref::sggx;
namespace mt = mcref::sggx_test;

class sggxFlakePhaseChi2 : public ::testing::TestWithParam<std::size_t> {};

TEST_P(sggxFlakePhaseChi2, MatchesPhaseFunction) {
  const auto cases = mt::sggx_chi2_cases();
  const mt::SggxChi2Case c = cases[GetParam()];
  const sg::Sggx s = c.sggx();
  const mcref::Vec3 wi = c.wi();
  mt::Chi2Options opt;
  opt.seed = 2000 + GetParam();
  opt.pole = -wi;
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [&](double u1, double u2) { return sg::sample_specular_flake_phase(s, 1.0, 1.0, wi, u1, u2).wo; },
      [&](mcref::Vec3 wo) { return sg::specular_flake_phase(s, wi, wo); }, opt);
  const double level = mt::sidak_significance(0.01, static_cast<int>(cases.size()));
  EXPECT_EQ(r.bad_samples, 0) << r.message;
  EXPECT_NEAR(r.pdf_mass, 1.0, 1e-6) << r.message;
  EXPECT_GT(r.p_value, level) << r.message;
  RecordProperty("p_value", std::to_string(r.p_value));
  std::printf("%s\n", r.message.c_str());
}

INSTANTIATE_TEST_SUITE_P(Cases, sggxFlakePhaseChi2,
                         ::testing::Range<std::size_t>(0, mt::sggx_chi2_cases().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return mt::sggx_chi2_case_name(mt::sggx_chi2_cases()[info.param], info.param);
                         });

}  // namespace
