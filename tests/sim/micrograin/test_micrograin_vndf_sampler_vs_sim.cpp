// The vNDF sampler (models/micrograin/vndf_sampler.h, vNDF paper Sec. 4)
// against the simulation: the histogram of sampled normals (validate model
// "vndf_sampler", 2e6 samples per incident direction, its own fixed seeds)
// must match the `vndf` table measured on explicit grain fields (the visible
// normals at the first grain hit), cell by cell. This checks the sampler
// against the geometry itself, not only against the paper's Eq. 13.
//
// Fields (tile 200, fixed seeds, 40 batches = realizations, 50000 rays per
// direction and batch):
//   iso:   tau0 = 0.7, beta = 1; theta_i = 20, 60, 80 deg; 9 theta_m x 8
//          folded phi_m_rel bins; seed 3101.
//   aniso: tau0 = 0.7, beta_x = 1.5, beta_y = 0.6; theta_i = 40, 70 deg,
//          phi_i = 0, 45 deg; 9 x 12 bins over [0, 2 pi); seed 3102.
//
// Statistics: per cell, z = (sim - sampler) / sqrt(se_sim^2 + se_sampler^2),
// se_sim the table's stderr over batches, se_sampler = sqrt(p (1 - p) / N) /
// (fold * solid angle) the binomial stderr of the sampler histogram (p = the
// cell's fraction of the N = 2e6 samples). Cells expected to hold fewer than
// 20 grain hits per batch are left out (sparse). Pass: every |z| below the
// Sidak bound at family-wise alpha = 0.001 over the compared cells, and the
// chi-square of the z's over the cells has p >= 0.001.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "models/core/statistics.h"
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/visible_filling_factor.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/tally/table.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {

constexpr double kSamplerSamples = 2e6;  // per direction, as in validate/micrograin/micrograin_models.cpp
constexpr double kAlpha = 0.001;
constexpr double kMinCount = 20;  // expected grain hits per batch in a compared cell

std::string cell_name(const Table& t, std::size_t flat) {
  std::vector<std::size_t> idx(t.axes.size());
  for (std::size_t d = t.axes.size(); d-- > 0;) {
    idx[d] = flat % t.axes[d].size();
    flat /= t.axes[d].size();
  }
  std::ostringstream s;
  s.precision(4);
  for (std::size_t d = 0; d < idx.size(); ++d) {
    const Axis& a = t.axes[d];
    s << (d ? ", " : "") << a.name << "=";
    if (a.kind == Axis::Kind::Bins) s << "[" << a.lower(idx[d]) << "," << a.upper(idx[d]) << ")";
    else s << a.values[idx[d]];
  }
  return s.str();
}

void compare(const std::string& label, const std::string& toml) {
  const Experiment ex = parse_experiment(toml, label + ".toml");
  SimulateOptions o;
  o.threads = 2;
  o.quiet = true;
  const std::vector<Table> tables = simulate(ex, o);
  ASSERT_EQ(tables.size(), 1u);
  const Table& t = tables[0];
  ASSERT_EQ(t.quantity, "vndf");
  const std::vector<double> sampler = evaluate_model("vndf_sampler", t, ex);
  ASSERT_EQ(sampler.size(), t.cells());

  const MicrograinGeometry& g = ex.micrograin;
  const micrograin::GrainField f{g.tau0, g.beta_x, g.beta_y};
  const double fold = g.anisotropic() ? 1.0 : 2.0;
  const double rays = static_cast<double>(ex.measures[0].samples);
  const Axis &ti = t.axes[0], &pi = t.axes[1], &th = t.axes[2], &ph = t.axes[3];
  struct Cell {
    std::size_t i;
    double sim, smp, se_sim, se_smp, z;
  };
  std::vector<Cell> cells;
  std::size_t sparse = 0;
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < pi.size(); ++b) {
      const double hits = micrograin::tau_plus(f, spherical_direction(ti.values[a], pi.values[b])) * rays;
      for (std::size_t c = 0; c < th.size(); ++c)
        for (std::size_t d = 0; d < ph.size(); ++d) {
          const std::size_t k = t.index({a, b, c, d});
          const double w = fold * (std::cos(th.lower(c)) - std::cos(th.upper(c))) * (ph.upper(d) - ph.lower(d));
          const double p = sampler[k] * w;  // fraction of the sampler's normals in the cell
          if (!(p * hits >= kMinCount)) {
            ++sparse;
            continue;
          }
          const double sim = t.value(k), se_sim = t.stderr_of(k);
          const double se_smp = std::sqrt(p * (1 - p) / kSamplerSamples) / w;
          ASSERT_TRUE(std::isfinite(sim) && std::isfinite(se_sim) && se_sim > 0) << label << " " << cell_name(t, k);
          cells.push_back({k, sim, sampler[k], se_sim, se_smp, (sim - sampler[k]) / std::hypot(se_sim, se_smp)});
        }
    }
  const std::size_t n = cells.size();
  ASSERT_GE(n, 10u) << label;
  double chi2 = 0, worst = 0;
  for (const Cell& c : cells) {
    chi2 += c.z * c.z;
    worst = std::max(worst, std::fabs(c.z));
  }
  const double bound = sidak_z_bound(kAlpha, static_cast<double>(n));
  const double pval = chi2_survival(chi2, static_cast<double>(n));
  std::printf("[ sampler  ] %-6s cells %3zu (sparse left out %zu)  max|z| %.2f (Sidak bound %.2f)  chi2/dof %.2f  p %.3g\n",
              label.c_str(), n, sparse, worst, bound, chi2 / static_cast<double>(n), pval);
  ::testing::Test::RecordProperty(label + "_max_abs_z", std::to_string(worst));
  ::testing::Test::RecordProperty(label + "_chi2_per_dof", std::to_string(chi2 / static_cast<double>(n)));
  EXPECT_LT(worst, bound) << label << ": a cell is beyond the Sidak bound";
  EXPECT_GE(pval, kAlpha) << label << ": chi2 = " << chi2 << " over " << n << " cells";
  if (worst >= bound || pval < kAlpha) {
    std::sort(cells.begin(), cells.end(), [](const Cell& x, const Cell& y) { return std::fabs(x.z) > std::fabs(y.z); });
    std::ostringstream s;
    s.precision(6);
    for (std::size_t k = 0; k < std::min<std::size_t>(12, n); ++k)
      s << "  " << cell_name(t, cells[k].i) << ": sim " << cells[k].sim << " +- " << cells[k].se_sim << "  sampler "
        << cells[k].smp << " +- " << cells[k].se_smp << "  z " << cells[k].z << "\n";
    ADD_FAILURE() << label << ": worst cells\n" << s.str();
  }
}

}  // namespace

TEST(MicrograinVndfSamplerVsSim, Isotropic) {
  compare("iso", R"(
[geometry]
kind = "micrograin"
tau0 = 0.7
beta = 1.0
tile = 200
[run]
seed = 3101
batches = 40
[[measure]]
quantity = "vndf"
theta_i_deg = [20, 60, 80]
theta_m_bins = 9
phi_m_bins = 8
samples = 50000
)");
}

TEST(MicrograinVndfSamplerVsSim, Anisotropic) {
  compare("aniso", R"(
[geometry]
kind = "micrograin"
tau0 = 0.7
beta_x = 1.5
beta_y = 0.6
tile = 200
[run]
seed = 3102
batches = 40
[[measure]]
quantity = "vndf"
theta_i_deg = [40, 70]
phi_i_deg = [0, 45]
theta_m_bins = 9
phi_m_bins = 12
samples = 50000
)");
}
