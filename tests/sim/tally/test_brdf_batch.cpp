// sim/tally/brdf_batch: one batch of the brdf tables, added direction by
// direction. Checked against values written out by hand from the tables'
// definitions (sim/tally/brdf_tally.h): a bin holds energy / (paths x its
// projected solid angle), components add up to the total, the albedo holds
// delta lobes too and the total the unscattered light. Against the whole-batch
// conversion it replaced: the same bits, whatever order the directions come in.
// Tables left out (make_brdf_tables' keep) have no cells and stay so, and the
// others get the same bits. A batch with a direction missing or added twice,
// or tables of another layout, are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
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

namespace {

// The conversion as it was before BrdfBatch (add_brdf_batch at 10f26d5: every
// direction's sums held, then one vector per table, then Table::add_batch): the
// reference for the bits.
void whole_batch_reference(const std::vector<std::vector<double>>& sums, double paths, const BrdfLayout& l,
                           std::vector<Table>& tables) {
  const int C = l.components(), H = l.hemispheres(), T = l.theta_o_bins, P = l.phi_bins;
  const double fold = l.folded ? 2.0 : 1.0;
  const double dphi = (l.folded ? kPi : 2 * kPi) / P;
  std::size_t table = 0;
  for (int h = 0; h < H; ++h) {
    std::vector<std::vector<double>> est(C + 1), albedo(1), delta(1);
    for (const std::vector<double>& s : sums) {
      for (int part = 0; part <= C; ++part)
        for (int t = 0; t < T; ++t) {
          const double a = static_cast<double>(t) / T, b = static_cast<double>(t + 1) / T;
          const double mu_lo = h == 0 ? 1 - b : a, mu_hi = h == 0 ? 1 - a : b;
          const double omega = fold * 0.5 * (mu_hi * mu_hi - mu_lo * mu_lo) * dphi;
          for (int p = 0; p < P; ++p)
            for (int k = 0; k < 3; ++k) {
              double e = 0;
              for (int c = 0; c < C; ++c)
                if (part == 0 || part == c + 1) e += s[((static_cast<std::size_t>(c * H + h) * T + t) * P + p) * 3 + k];
              est[part].push_back(e / (paths * omega));
            }
        }
      for (int kind = 0; kind < 2; ++kind) {
        std::vector<double>& dst = kind == 0 ? albedo[0] : delta[0];
        for (int part = 0; part <= C; ++part)
          for (int k = 0; k < 3; ++k) {
            double e = 0;
            for (int c = 0; c < C; ++c) {
              if (part < C && part != c) continue;
              const std::size_t i = static_cast<std::size_t>(c * H + h) * 3 + k;
              const double non_delta = s[l.binned_size() + i], in_delta = s[l.binned_size() + C * H * 3 + i];
              e += kind == 0 ? non_delta + in_delta : in_delta;
            }
            if (part == C) e += s[l.binned_size() + 2 * C * H * 3 + h * 3 + k];
            dst.push_back(e / paths);
          }
      }
    }
    for (int part = 0; part <= C; ++part) tables[table++].add_batch(est[part]);
    tables[table++].add_batch(albedo[0]);
    tables[table++].add_batch(delta[0]);
  }
}

}  // namespace

// 3 batches, directions added in reverse order, against the whole-batch
// conversion: sum, sum_sq and batches equal to the bit, folded or not, with
// and without transmission; a table after the brdf tables is left alone.
TEST(BrdfBatch, SameBitsAsTheWholeBatchConversion) {
  const std::size_t D = kThetaI.size() * kPhiI.size();
  for (const bool folded : {true, false})
    for (const bool transmission : {true, false}) {
      BrdfLayout l = layout();
      l.folded = folded;
      l.transmission = transmission;
      std::vector<Table> reference = make_brdf_tables("brdf", kThetaI, kPhiI, l);
      reference.emplace_back("other", "other", std::vector<Axis>{Axis::points("x", "1", {0, 1})});
      std::vector<Table> streamed = reference;
      Rng rng(8);
      for (int b = 0; b < 3; ++b) {
        std::vector<std::vector<double>> sums;
        for (std::size_t d = 0; d < D; ++d) sums.push_back(random_sums(l, rng));
        whole_batch_reference(sums, 500, l, reference);
        BrdfBatch batch(l, 500, streamed);
        for (std::size_t d = D; d-- > 0;) batch.add(d, sums[d]);
        batch.close();
      }
      for (std::size_t i = 0; i + 1 < reference.size(); ++i) {
        EXPECT_EQ(streamed[i].batches, 3) << streamed[i].name;
        EXPECT_EQ(reference[i].sum, streamed[i].sum) << reference[i].name << " folded " << folded;
        EXPECT_EQ(reference[i].sum_sq, streamed[i].sum_sq) << reference[i].name << " folded " << folded;
      }
      const Table& other = streamed.back();
      EXPECT_EQ(other.batches, 0);
      EXPECT_EQ(other.sum, std::vector<double>(2, 0.0));
    }
}

// 2 batches into all the tables and into tables of which keep names 4 (a
// total, two components of either hemisphere, an albedo): the 4 the same
// bits, the others without cells and never counted.
TEST(BrdfBatch, TablesLeftOutStayEmptyAndTheOthersKeepTheirBits) {
  const BrdfLayout l = layout();
  const std::vector<std::string> keep{"brdf_btdf_order3", "brdf", "brdf_order1_volume", "brdf_btdf_albedo"};
  std::vector<Table> all = make_brdf_tables("brdf", kThetaI, kPhiI, l);
  std::vector<Table> some = make_brdf_tables("brdf", kThetaI, kPhiI, l, keep);
  ASSERT_EQ(all.size(), some.size());
  Rng rng(10);
  for (int b = 0; b < 2; ++b) {
    BrdfBatch full(l, 300, all), part(l, 300, some);
    for (std::size_t d = 0; d < kThetaI.size() * kPhiI.size(); ++d) {
      const std::vector<double> s = random_sums(l, rng);
      full.add(d, s);
      part.add(d, s);
    }
    full.close();
    part.close();
  }
  int kept = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].name, some[i].name);
    EXPECT_EQ(all[i].axes.size(), some[i].axes.size()) << some[i].name;  // the outline stays
    if (std::find(keep.begin(), keep.end(), some[i].name) != keep.end()) {
      ++kept;
      EXPECT_EQ(some[i].batches, 2) << some[i].name;
      EXPECT_EQ(all[i].sum, some[i].sum) << some[i].name;
      EXPECT_EQ(all[i].sum_sq, some[i].sum_sq) << some[i].name;
    } else {
      EXPECT_EQ(some[i].cells(), 0u) << some[i].name;
      EXPECT_TRUE(some[i].sum_sq.empty()) << some[i].name;
      EXPECT_EQ(some[i].batches, 0) << some[i].name;
    }
  }
  EXPECT_EQ(kept, 4);
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
  BrdfLayout finer = l;
  finer.phi_bins = 12;  // tables of another layout, as many of them
  std::vector<Table> other_layout = make_brdf_tables("brdf", kThetaI, kPhiI, finer);
  EXPECT_THROW(BrdfBatch(l, 100, other_layout), std::logic_error);
}
