// Chi-square goodness of fit of the SGGX visible-normal sampler against
// visible_ndf (Heitz 2015 Sec. 5): 10^6 samples per case, 64 x 128 equal-area
// (cos, phi) bins around the viewing direction w, cells below 5 expected
// pooled, level 0.01 Sidak-corrected over the cases of this file, fixed seeds.
#include <gtest/gtest.h>

#include <cstdio>

#include "models/sggx/sggx_distribution.h"
#include "tests/models/sggx_chi2.h"
#include "tests/models/sggx_chi2_cases.h"

namespace {

namespace sg = mcref::sggx;
namespace mt = mcref::sggx_test;

class sggxVndfChi2 : public ::testing::TestWithParam<std::size_t> {};

TEST_P(sggxVndfChi2, MatchesVisibleNdf) {
  const auto cases = mt::sggx_chi2_cases();
  const mt::SggxChi2Case c = cases[GetParam()];
  const sg::Sggx s = c.sggx();
  const mcref::Vec3 w = c.wi();
  mt::Chi2Options opt;
  opt.seed = 1000 + GetParam();
  opt.pole = w;  // the kink of <w.m>^+ falls on a bin edge
  const mt::Chi2Result r = mt::chi2_sphere_test(
      [&](double u1, double u2) { return sg::sample_visible_normal(s, w, u1, u2); },
      [&](mcref::Vec3 m) { return sg::visible_ndf(s, w, m); }, opt);
  const double level = mt::sidak_significance(0.01, static_cast<int>(cases.size()));
  EXPECT_EQ(r.bad_samples, 0) << r.message;
  EXPECT_NEAR(r.pdf_mass, 1.0, 1e-6) << r.message;
  EXPECT_GT(r.p_value, level) << r.message;
  RecordProperty("p_value", std::to_string(r.p_value));
  std::printf("%s\n", r.message.c_str());
}

INSTANTIATE_TEST_SUITE_P(Cases, sggxVndfChi2, ::testing::Range<std::size_t>(0, mt::sggx_chi2_cases().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return mt::sggx_chi2_case_name(mt::sggx_chi2_cases()[info.param], info.param);
                         });

}  // namespace
