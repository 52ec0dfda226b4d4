// sim/tally/brdf_batch: one batch of the brdf tables, added direction by
// direction. Checked against values written out by hand from the tables'
// definitions (sim/tally/brdf_tally.h): a bin holds energy / (paths x its
// projected solid angle), components add up to the total, the albedo holds
// delta lobes too and the total the unscattered light; the order in which
// directions come in changes no bit; a batch with a direction missing or
// added twice is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "models/core/rng.h"
#include "models/core/vec.h"
#include "sim/tally/brdf_batch.h"
#include "sim/tally/brdf_tally.h"

using namespace mcref;

namespace {

BrdfLayout layout() {
  BrdfLayout l;
  l.theta_o_bins = 4;
  l.phi_bins = 6;
  l.folded = false;
  l.transmission = true;
  l.order1_classes = {"volume", "substrate"};
  return l;
}

const std::vector<double> kThetaI{0.2, 0.9, 1.3}, kPhiI{0.0, 2.0};

// Random sums of one direction: every slot an independent uniform in [0, 1).
std::vector<double> random_sums(const BrdfLayout& l, Rng& rng) {
  std::vector<double> s(l.sums_size());
  for (double& x : s) x = rng.uniform();
  return s;
}

const Table& named(const std::vector<Table>& tables, const std::string& name) {
  for (const Table& t : tables)
    if (t.name == name) return t;
  throw std::logic_error("no table " + name);
}

}  // namespace

TEST(BrdfBatch, BinsAreEnergyOverPathsTimesProjectedSolidAngle) {
  const BrdfLayout l = layout();
  const int C = l.components(), H = l.hemispheres(), T = l.theta_o_bins, P = l.phi_bins;
  const double paths = 1000;
  std::vector<Table> tables = make_brdf_tables("brdf", kThetaI, kPhiI, l);
  Rng rng(7);
  std::vector<std::vector<double>> sums;
  BrdfBatch batch(l, paths, tables);
  for (std::size_t d = 0; d < kThetaI.size() * kPhiI.size(); ++d) {
    sums.push_back(random_sums(l, rng));
    batch.add(d, sums.back());
  }
  batch.close();
  const std::vector<std::string> comps = l.component_names();
  for (int h = 0; h < H; ++h) {
    const std::string hemi = h == 0 ? "brdf" : "brdf_btdf";
    for (std::size_t d = 0; d < sums.size(); ++d) {
      const std::vector<double>& s = sums[d];
      for (int t = 0; t < T; ++t) {
        // |cos theta_o| in [1 - (t+1)/T, 1 - t/T] above, [t/T, (t+1)/T] below; integral of |cos| d omega.
        const double mu0 = h == 0 ? 1.0 - (t + 1.0) / T : t / static_cast<double>(T), mu1 = mu0 + 1.0 / T;
        const double omega = 0.5 * (mu1 * mu1 - mu0 * mu0) * (2 * kPi / P);
        for (int p = 0; p < P; ++p)
          for (int k = 0; k < 3; ++k) {
            const std::size_t cell = ((d * T + t) * P + p) * 3 + k;
            double total = 0;
            for (int c = 0; c < C; ++c) {
              const double e = s[((static_cast<std::size_t>(c * H + h) * T + t) * P + p) * 3 + k];
              total += e;
              EXPECT_NEAR(named(tables, hemi + "_" + comps[c]).value(cell), e / (paths * omega), 1e-12 * e / (paths * omega));
            }
            EXPECT_NEAR(named(tables, hemi).value(cell), total / (paths * omega), 1e-12 * total / (paths * omega));
          }
      }
      // Albedo: per component its energy in and out of delta lobes; the total adds
      // every component and the unscattered light. Delta: the delta-lobe part only.
      for (int k = 0; k < 3; ++k) {
        double albedo = 0, delta = 0;
        for (int c = 0; c < C; ++c) {
          const std::size_t i = static_cast<std::size_t>(c * H + h) * 3 + k;
          const double non_delta = s[l.binned_size() + i], in_delta = s[l.binned_size() + C * H * 3 + i];
          EXPECT_DOUBLE_EQ(named(tables, hemi + "_albedo").value((d * (C + 1) + c) * 3 + k), (non_delta + in_delta) / paths);
          EXPECT_DOUBLE_EQ(named(tables, hemi + "_delta").value((d * (C + 1) + c) * 3 + k), in_delta / paths);
          albedo += non_delta + in_delta;
          delta += in_delta;
        }
        const double unscattered = s[l.binned_size() + 2 * C * H * 3 + h * 3 + k];
        EXPECT_NEAR(named(tables, hemi + "_albedo").value((d * (C + 1) + C) * 3 + k), (albedo + unscattered) / paths, 1e-15);
        EXPECT_NEAR(named(tables, hemi + "_delta").value((d * (C + 1) + C) * 3 + k), (delta + unscattered) / paths, 1e-15);
      }
    }
  }
  for (const Table& t : tables) EXPECT_EQ(t.batches, 1) << t.name;
}

TEST(BrdfBatch, DirectionOrderChangesNoBit) {
  const BrdfLayout l = layout();
  const std::size_t D = kThetaI.size() * kPhiI.size();
  std::vector<Table> in_order = make_brdf_tables("brdf", kThetaI, kPhiI, l), reversed = in_order;
  Rng rng(8);
  for (int b = 0; b < 3; ++b) {
    std::vector<std::vector<double>> sums;
    for (std::size_t d = 0; d < D; ++d) sums.push_back(random_sums(l, rng));
    add_brdf_batch(sums, 500, l, in_order);
    BrdfBatch batch(l, 500, reversed);
    for (std::size_t d = D; d-- > 0;) batch.add(d, sums[d]);
    batch.close();
  }
  for (std::size_t i = 0; i < in_order.size(); ++i) {
    EXPECT_EQ(in_order[i].batches, 3);
    EXPECT_EQ(reversed[i].batches, 3);
    EXPECT_EQ(in_order[i].sum, reversed[i].sum) << in_order[i].name;
    EXPECT_EQ(in_order[i].sum_sq, reversed[i].sum_sq) << in_order[i].name;
  }
}

TEST(BrdfBatch, RefusesAMissingOrRepeatedDirectionAndOtherLayouts) {
  const BrdfLayout l = layout();
  std::vector<Table> tables = make_brdf_tables("brdf", kThetaI, kPhiI, l);
  Rng rng(9);
  const std::vector<double> s = random_sums(l, rng);
  BrdfBatch batch(l, 100, tables);
  for (std::size_t d = 0; d + 1 < kThetaI.size() * kPhiI.size(); ++d) batch.add(d, s);
  EXPECT_THROW(batch.add(0, s), std::logic_error);                                    // twice
  EXPECT_THROW(batch.add(kThetaI.size() * kPhiI.size(), s), std::logic_error);        // no such direction
  EXPECT_THROW(batch.add(5, std::vector<double>(s.size() - 1)), std::logic_error);    // another layout's sums
  EXPECT_THROW(batch.close(), std::logic_error);                                      // direction 5 missing
  for (const Table& t : tables) EXPECT_EQ(t.batches, 0) << t.name;
  batch.add(5, s);
  batch.close();
  for (const Table& t : tables) EXPECT_EQ(t.batches, 1) << t.name;
  std::vector<Table> too_few(tables.begin(), tables.end() - 1);
  EXPECT_THROW(BrdfBatch(l, 100, too_few), std::logic_error);
}
