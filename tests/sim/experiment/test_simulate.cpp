// sim/experiment/simulate: determinism (thread count, seeds) and every micrograin
// estimator against its exact model (validate/model_evaluation), cell by cell,
// with the tables' own standard errors.
//
// Statistical rule: z = (sim - model) / stderr per cell (stderr from the
// batches: realizations of the field). A table passes if every |z| stays below
// max(4, Sidak bound for alpha = 0.001 over its cells, normal quantile) and,
// with 10 cells or more, the joint test has p >= 0.001: the sign-flip test over
// the batches (validate/sign_flip.h, as `mcref validate` judges an exact model;
// exact whatever the cells' correlation, 48 batches), or for a table without
// batch values the chi-square of the z's over the cells taken as independent. Binned density tables leave out cells expected to hold fewer
// than 20 samples per batch (stated per test); cells identical in every batch
// (zero stderr, e.g. G1 = 1 where nothing can occlude) carry no variance and
// are left out of the z test (only a gross |sim - model| < 0.01 check).
// Seeds, samples and batches are in each experiment's TOML.
//
// The model tests use tile 200 (the default): the realization-to-realization
// variance is common to all cells of a table, so on small tiles the cells'
// z's are correlated and the chi-square over cells is not chi-square
// distributed (on tile 60, g1_conditional's chi2/dof ranged 0.8..2.1 over
// eight seeds). The sign-flip test allows for that; a large tile keeps the
// path noise, independent per cell, dominant, and so the test's power.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/core/statistics.h"
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"
#include "models/micrograin/visible_filling_factor.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/tally/table.h"
#include "tests/models/chi2.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {

const char* kIso = R"(
[geometry]
kind = "micrograin"
tau0 = 0.5
beta = 0.8
tile = 200
)";

const char* kAniso = R"(
[geometry]
kind = "micrograin"
tau0 = 0.4
beta_x = 0.5
beta_y = 1.5
tile = 200
)";

std::string run_section(int seed, int batches) {
  return "[run]\nseed = " + std::to_string(seed) + "\nbatches = " + std::to_string(batches) + "\n";
}

std::vector<Table> run(const Experiment& e, int threads) {
  SimulateOptions o;
  o.threads = threads;
  o.quiet = true;
  return simulate(e, o);
}

std::vector<Table> run(const std::string& toml, int threads = 2) {
  return run(parse_experiment(toml, "test_simulate.toml"), threads);
}

const Table& table(const std::vector<Table>& ts, const std::string& name) {
  for (const Table& t : ts)
    if (t.name == name) return t;
  throw std::runtime_error("no table " + name);
}

bool bit_identical(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

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

// Compares a table with model values; `expected_counts` (optional) is the
// expected number of samples per batch in each cell, cells below `min_count`
// are left out; with `empty_cells_allowed`, NaN cells (a batch without a
// sample there) are left out too. Prints one summary line, and the worst
// cells on failure.
void expect_matches_model(const Table& t, const std::vector<double>& model, const std::string& label,
                          const std::vector<double>& expected_counts = {}, double min_count = 20,
                          bool empty_cells_allowed = false) {
  ASSERT_EQ(model.size(), t.cells()) << label;
  struct Cell {
    std::size_t i;
    double sim, model, se, z;
  };
  std::vector<Cell> cells;
  std::size_t sparse = 0, empty = 0, constant = 0;
  for (std::size_t i = 0; i < t.cells(); ++i) {
    if (!expected_counts.empty() && !(expected_counts[i] >= min_count)) {
      ++sparse;
      continue;
    }
    const double sim = t.value(i), se = t.stderr_of(i);
    if (std::isnan(sim) && empty_cells_allowed) {
      ++empty;  // some batch had no sample in the cell
      continue;
    }
    if (!std::isfinite(sim) || !std::isfinite(model[i]) || !std::isfinite(se)) {
      ADD_FAILURE() << label << ": undefined cell " << cell_name(t, i) << " sim " << sim << " model " << model[i]
                    << " stderr " << se;
      continue;
    }
    if (se == 0) {
      ++constant;
      EXPECT_NEAR(sim, model[i], 0.01) << label << ": constant cell " << cell_name(t, i);
      continue;
    }
    cells.push_back({i, sim, model[i], se, (sim - model[i]) / se});
  }
  const std::size_t n = cells.size();
  ASSERT_GT(n, 0u) << label;
  double chi2 = 0, worst = 0;
  for (const Cell& c : cells) {
    chi2 += c.z * c.z;
    worst = std::max(worst, std::fabs(c.z));
  }
  const double bound = std::max(4.0, sidak_z_bound(0.001, static_cast<double>(n)));
  double p = test::regularized_gamma_q(0.5 * n, 0.5 * chi2);
  const char* test = "chi2, cells as independent";
  if (t.has_batch_values()) {
    std::vector<double> compared(t.cells(), NAN);  // the cells left out have no model value
    for (const Cell& c : cells) compared[c.i] = c.model;
    const Comparison joint = compare(t.values(), t.stderrs(), compared, t.batches, {}, t.channels(), t.batch_values);
    EXPECT_EQ(joint.cells, n) << label;
    EXPECT_EQ(joint.joint_test, "sign-flip") << label;
    p = joint.p_value;
    test = "sign-flip";
  }
  std::printf("[ model    ] %-44s cells %3zu (left out: %zu sparse, %zu empty, %zu constant)  max|z| %.2f "
              "(bound %.2f)  chi2/dof %.2f  p %.3g (%s)\n",
              label.c_str(), n, sparse, empty, constant, worst, bound, chi2 / n, p, test);
  bool ok = worst < bound;
  EXPECT_LT(worst, bound) << label << ": a cell is beyond the Sidak bound";
  if (n >= 10) {
    EXPECT_GE(p, 0.001) << label << ": chi2 = " << chi2 << " over " << n << " cells";
    ok = ok && p >= 0.001;
  }
  if (!ok) {
    std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return std::fabs(a.z) > std::fabs(b.z); });
    std::ostringstream s;
    s.precision(6);
    for (std::size_t k = 0; k < std::min<std::size_t>(12, n); ++k)
      s << "  " << cell_name(t, cells[k].i) << ": sim " << cells[k].sim << " model " << cells[k].model << " stderr "
        << cells[k].se << " z " << cells[k].z << "\n";
    ADD_FAILURE() << label << ": worst cells\n" << s.str();
  }
}

micrograin::GrainField grain_field(const MicrograinGeometry& g) { return {g.tau0, g.beta_x, g.beta_y}; }

}  // namespace

// ---------------------------------------------------------------- determinism

// Every micrograin quantity; 3 batches, samples above one chunk (4096) so
// several chunks run in parallel; tile 30.
const char* kAllQuantities = R"(
[[measure]]
quantity = "p1"
samples = 9000
r_bins = 12
[[measure]]
quantity = "ndf"
samples = 9000
theta_m_bins = 6
[[measure]]
quantity = "tau_plus"
theta_i_deg = [0, 60, 85]
phi_i_deg = [0, 30]
samples = 9000
[[measure]]
quantity = "tau_height"
theta_i_deg = [45]
h_points = 5
samples = 9000
[[measure]]
quantity = "g1"
theta_i_deg = [30, 80]
theta_m_bins = 4
phi_m_bins = 4
samples = 9000
[[measure]]
quantity = "pore_visibility"
theta_i_deg = [30]
theta_o_deg = [30, 70]
phi_deg = [0, 180]
samples = 9000
[[measure]]
quantity = "vndf"
theta_i_deg = [50]
theta_m_bins = 4
phi_m_bins = 4
samples = 9000
)";

std::string all_quantities(const char* geometry, int seed) {
  std::string s = std::string(geometry) + run_section(seed, 3) + kAllQuantities;
  const auto at = s.find("tile = 200");
  return s.replace(at, 10, "tile = 30");
}

TEST(SimulateDeterminism, BitIdenticalForOneAndTwoThreads) {
  for (const char* geometry : {kIso, kAniso}) {
    const Experiment e = parse_experiment(all_quantities(geometry, 5), "test_simulate.toml");
    const std::vector<Table> one = run(e, 1), two = run(e, 2);
    ASSERT_EQ(one.size(), 9u);  // 7 measures; g1 and pore_visibility make two tables each
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t k = 0; k < one.size(); ++k) {
      EXPECT_EQ(one[k].name, two[k].name);
      EXPECT_EQ(one[k].batches, 3);
      EXPECT_TRUE(bit_identical(one[k].sum, two[k].sum)) << one[k].name;
      EXPECT_TRUE(bit_identical(one[k].sum_sq, two[k].sum_sq)) << one[k].name;
    }
  }
}

TEST(SimulateDeterminism, SameSeedSameTablesOtherSeedOtherTables) {
  const std::vector<Table> a = run(all_quantities(kIso, 5)), b = run(all_quantities(kIso, 5));
  const std::vector<Table> c = run(all_quantities(kIso, 6));
  // --set run.seed=6 is the same experiment as seed = 6 in the file.
  const std::vector<Table> d =
      run(parse_experiment(all_quantities(kIso, 5), "test_simulate.toml", {"run.seed=6"}), 2);
  ASSERT_EQ(a.size(), c.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(bit_identical(a[k].sum, b[k].sum)) << a[k].name;
    EXPECT_TRUE(bit_identical(a[k].sum_sq, b[k].sum_sq)) << a[k].name;
    EXPECT_FALSE(bit_identical(a[k].sum, c[k].sum)) << a[k].name << " does not depend on the seed";
    EXPECT_TRUE(bit_identical(c[k].sum, d[k].sum)) << a[k].name;
  }
  // Most p1 cells move with the seed.
  const Table& pa = table(a, "p1");
  const Table& pc = table(c, "p1");
  int differ = 0;
  for (std::size_t i = 0; i < pa.cells(); ++i) differ += pa.sum[i] != pc.sum[i];
  EXPECT_GE(differ, static_cast<int>(pa.cells()) - 1);
}

// ------------------------------------------------------ estimators vs models

// One run per test and field (ctest runs every test in its own process):
// 48 batches (so a cell's z is close to normal: Student t with 47 dof),
// modest samples per batch (so path noise, independent per cell, dominates
// the realization variance that all cells share). Isotropic field seed 101,
// anisotropic seed 102.
struct Field {
  const char* label;
  const char* geometry;
  int seed;
  const char* p1;
  const char* ndf;
  const char* tau_plus;
  const char* tau_height;
  const char* g1;
  const char* pore_visibility;
  const char* vndf;
};

const Field kFields[] = {
    {"iso", kIso, 101,
     "quantity = \"p1\"\nsamples = 60000\nr_bins = 30\nr_max = 3\n",
     "quantity = \"ndf\"\nsamples = 60000\ntheta_m_bins = 18\nphi_m_bins = 1\n",
     "quantity = \"tau_plus\"\ntheta_i_deg = [0, 30, 60, 75, 85]\nsamples = 20000\n",
     "quantity = \"tau_height\"\ntheta_i_deg = [0, 45, 75]\nh_points = 10\nsamples = 20000\n",
     "quantity = \"g1\"\ntheta_i_deg = [20, 45, 70, 85]\ntheta_m_bins = 6\nphi_m_bins = 6\nsamples = 20000\n",
     "quantity = \"pore_visibility\"\ntheta_i_deg = [30, 60]\ntheta_o_deg = [30, 60, 80]\nphi_deg = [0, 90, 180]\n"
     "samples = 30000\n",
     "quantity = \"vndf\"\ntheta_i_deg = [40, 75]\ntheta_m_bins = 9\nphi_m_bins = 9\nsamples = 60000\n"},
    {"aniso", kAniso, 102,
     "quantity = \"p1\"\nsamples = 60000\nr_bins = 30\nr_max = 3\n",
     "quantity = \"ndf\"\nsamples = 100000\ntheta_m_bins = 9\nphi_m_bins = 12\n",
     "quantity = \"tau_plus\"\ntheta_i_deg = [30, 60, 85]\nphi_i_deg = [0, 45, 90]\nsamples = 20000\n",
     "quantity = \"tau_height\"\ntheta_i_deg = [60]\nphi_i_deg = [0, 90]\nh_points = 10\nsamples = 20000\n",
     "quantity = \"g1\"\ntheta_i_deg = [60]\nphi_i_deg = [0, 90]\ntheta_m_bins = 6\nphi_m_bins = 8\nsamples = 20000\n",
     "quantity = \"pore_visibility\"\ntheta_i_deg = [45]\nphi_i_deg = [30]\ntheta_o_deg = [30, 70]\n"
     "phi_deg = [0, 90, 180]\nsamples = 30000\n",
     "quantity = \"vndf\"\ntheta_i_deg = [60]\nphi_i_deg = [0, 60]\ntheta_m_bins = 9\nphi_m_bins = 12\nsamples = 60000\n"},
};

struct FieldRun {
  std::string label;
  Experiment experiment;
  std::vector<Table> tables;
  const Table& operator[](const std::string& name) const { return table(tables, name); }
  const MicrograinGeometry& geometry() const { return experiment.micrograin; }
  double samples() const { return static_cast<double>(experiment.measures[0].samples); }
};

// Simulates one measure (a member of Field) on a field, 48 batches.
FieldRun run_measure(const Field& f, const char* Field::*measure) {
  FieldRun r;
  r.label = f.label;
  r.experiment = parse_experiment(std::string(f.geometry) + run_section(f.seed, 48) + "[[measure]]\n" + f.*measure,
                                  "test_simulate.toml");
  SimulateOptions o;
  o.threads = 2;
  o.quiet = true;
  o.keep_batch_values = true;  // for the sign-flip test (the sums are the same bits)
  r.tables = simulate(r.experiment, o);
  return r;
}

// p1 (60000 points per batch, 30 bins on [0, 3] unit-space radii) against
// the closest-centre CDF integrated over each bin. Expected counts per batch:
// model * bin width * samples.
TEST(SimulateVsModel, P1MatchesClosestGrainDistribution) {
  for (const Field& f : kFields) {
    const FieldRun run = run_measure(f, &Field::p1);
    const FieldRun* r = &run;
    const Table& t = (*r)["p1"];
    const std::vector<double> model = evaluate_model("p1_eq10", t, r->geometry());
    std::vector<double> counts(t.cells());
    for (std::size_t b = 0; b < t.cells(); ++b)
      counts[b] = model[b] * (t.axes[0].upper(b) - t.axes[0].lower(b)) * r->samples();
    expect_matches_model(t, model, "p1 vs p1_eq10, " + r->label, counts);
  }
}

// NDF at normal incidence (iso: 60000 rays, 18 theta bins; aniso: 100000
// rays, 9 theta x 12 phi bins) against Eq. 16/17 cosine-weighted bin
// averages. Expected counts per batch: model * projected solid angle * tau0 * rays.
TEST(SimulateVsModel, NdfMatchesEq17) {
  for (const Field& f : kFields) {
    const FieldRun run = run_measure(f, &Field::ndf);
    const FieldRun* r = &run;
    const Table& t = (*r)["ndf"];
    const std::vector<double> model = evaluate_model("ndf_eq17", t, r->geometry());
    std::vector<double> counts(t.cells());
    const Axis &th = t.axes[0], &ph = t.axes[1];
    for (std::size_t a = 0; a < th.size(); ++a)
      for (std::size_t b = 0; b < ph.size(); ++b) {
        const double s0 = std::sin(th.lower(a)), s1 = std::sin(th.upper(a));
        const double w = 0.5 * (s1 * s1 - s0 * s0) * (ph.upper(b) - ph.lower(b));
        counts[a * ph.size() + b] = model[a * ph.size() + b] * w * r->geometry().tau0 * r->samples();
      }
    expect_matches_model(t, model, "ndf vs ndf_eq17, " + r->label, counts);
  }
}

// tau+ (20000 rays per direction) against Eq. 22.
TEST(SimulateVsModel, TauPlusMatchesEq22) {
  for (const Field& f : kFields) {
    const FieldRun r = run_measure(f, &Field::tau_plus);
    expect_matches_model(r["tau_plus"], evaluate_model("tau_plus_eq22", r["tau_plus"], r.geometry()),
                         "tau_plus vs tau_plus_eq22, " + r.label);
  }
}

// On a small periodic tile (40 radii, beta 1: c tan(theta) + 2 reaches the
// side at atan(38) = 88.49 deg) tau+ still matches Eq. 22 just inside that
// limit, where no ray can meet a grain's periodic copy (seed 151, 48 batches
// of 20000 rays); past it the direction is refused (at 89 deg, 1.4 sides, the
// estimate was 0.678 +- 0.013 against 0.776).
TEST(SimulateVsModel, TauPlusMatchesEq22UpToTheTileLimit) {
  const std::string geometry = "[geometry]\nkind = \"micrograin\"\ntau0 = 0.05\nbeta = 1.0\ntile = 40\n";
  const auto experiment = [&](const std::string& angles) {
    return geometry + run_section(151, 48) + "[[measure]]\nquantity = \"tau_plus\"\ntheta_i_deg = " + angles +
           "\nsamples = 20000\n";
  };
  const Experiment e = parse_experiment(experiment("[60, 85, 88.4]"), "test_simulate.toml");
  SimulateOptions o;
  o.threads = 2;
  o.quiet = true;
  o.keep_batch_values = true;
  const std::vector<Table> t = simulate(e, o);
  expect_matches_model(table(t, "tau_plus"), evaluate_model("tau_plus_eq22", table(t, "tau_plus"), e.micrograin),
                       "tau_plus vs tau_plus_eq22, tile 40");
  try {
    parse_experiment(experiment("[88.6]"), "test_simulate.toml");
    ADD_FAILURE() << "88.6 deg on a tile of 40 radii was accepted";
  } catch (const ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("at most 88.49"), std::string::npos) << err.what();
  }
}

// tau(i, h), h = 0, 0.1, ..., 0.9 (20000 rays per direction), against
// 1 - exp(-rho' sigma(i, h)). Cells of one direction share rays (cumulative
// in h), so their z's are correlated.
TEST(SimulateVsModel, TauHeightMatchesProjectedCapArea) {
  for (const Field& f : kFields) {
    const FieldRun r = run_measure(f, &Field::tau_height);
    expect_matches_model(r["tau_height"], evaluate_model("tau_height_sigma", r["tau_height"], r.geometry()),
                         "tau_height vs tau_height_sigma, " + r.label);
  }
}

// G1 (20000 sampled height-field points per direction). The marginal against
// tau+(i) / (tau0 (1 + Lambda_quad(i))) and against the projected-area
// average of G_dist (both exact); the conditional table against
// G_dist(i, h(m)) (cells a batch left empty are NaN and left out).
TEST(SimulateVsModel, G1MatchesVisibleAreaRatioAndDistantMasking) {
  for (const Field& f : kFields) {
    const FieldRun run = run_measure(f, &Field::g1);
    const FieldRun* r = &run;
    const Table& g1 = (*r)["g1"];
    expect_matches_model(g1, evaluate_model("g1_exact_tau_plus", g1, r->geometry()), "g1 vs g1_exact_tau_plus, " + r->label);
    expect_matches_model(g1, evaluate_model("g1_g_dist", g1, r->geometry()), "g1 vs g1_g_dist, " + r->label);
    const Table& c = (*r)["g1_conditional"];
    expect_matches_model(c, evaluate_model("g1_conditional_g_dist", c, r->geometry()),
                         "g1_conditional vs g1_conditional_g_dist, " + r->label, {}, 0, true);
  }
}

// Pore visibility (30000 base points per batch; 1 - tau0 of them are pores):
// the per-batch product V(i) V(o) against
// ((1 - tau+(i)) / (1 - tau0)) ((1 - tau+(o)) / (1 - tau0)). The anisotropic
// run has phi_i = 30 degrees (the model reads it from the table's phi_i).
TEST(SimulateVsModel, PoreVisibilityProductMatchesTauPlus) {
  for (const Field& f : kFields) {
    const FieldRun r = run_measure(f, &Field::pore_visibility);
    const Table& t = r["pore_visibility_independent"];
    expect_matches_model(t, evaluate_model("pore_visibility_product_eq22", t, r.geometry()),
                         "pore_visibility_independent vs product_eq22, " + r.label);
    // The joint visibility is not the product (visibilities toward i and o
    // are correlated): printed for information, not tested here (its exact
    // model, pore_visibility_union: tests/validate/micrograin/test_exact_models_vs_sim.cpp).
    const Table& joint = r["pore_visibility"];
    const std::vector<double> product = evaluate_model("pore_visibility_independence_eq24", joint, r.geometry());
    for (std::size_t i = 0; i < joint.cells(); ++i)
      std::printf("[ info     ] pore_visibility %s %s: joint %.4f +- %.4f, independent %.4f\n", r.label.c_str(),
                  cell_name(joint, i).c_str(), joint.value(i), joint.stderr_of(i), product[i]);
  }
}

// vNDF (60000 rays per direction; iso 9 x 9 bins with folded azimuth, aniso
// 9 x 12 over 2 pi) against visible_ndf bin averages. Expected counts per
// batch: model * (folded) solid angle * tau+(i) * rays; below 20 left out.
TEST(SimulateVsModel, VndfMatchesVisibleNdf) {
  for (const Field& f : kFields) {
    const FieldRun run = run_measure(f, &Field::vndf);
    const FieldRun* r = &run;
    const Table& t = (*r)["vndf"];
    const std::vector<double> model = evaluate_model("vndf_eq13", t, r->geometry());
    const bool folded = !r->geometry().anisotropic();
    const Axis &ti = t.axes[0], &pi = t.axes[1], &th = t.axes[2], &ph = t.axes[3];
    std::vector<double> counts(t.cells());
    for (std::size_t a = 0; a < ti.size(); ++a)
      for (std::size_t b = 0; b < pi.size(); ++b) {
        const double hits = micrograin::tau_plus(grain_field(r->geometry()), spherical_direction(ti.values[a], pi.values[b])) *
                            r->samples();
        for (std::size_t c = 0; c < th.size(); ++c)
          for (std::size_t d = 0; d < ph.size(); ++d) {
            const std::size_t k = t.index({a, b, c, d});
            const double omega =
                (folded ? 2 : 1) * (std::cos(th.lower(c)) - std::cos(th.upper(c))) * (ph.upper(d) - ph.lower(d));
            counts[k] = model[k] * omega * hits;
          }
      }
    expect_matches_model(t, model, "vndf vs vndf_eq13, " + r->label, counts);
  }
}

// tau+ at theta = 85 degrees does not depend on the tile: tiles 40 and 160,
// seeds 108 / 109, 32 batches, 50000 rays each; tau0 = 0.5 and 0.1 (long
// free paths). |difference| < 4 combined standard errors.
TEST(SimulateVsModel, TauPlusAtGrazingIncidenceIsTileSizeInvariant) {
  for (double tau0 : {0.5, 0.1}) {
    double v[2], se[2];
    int k = 0;
    for (int tile : {40, 160}) {
      const Experiment e = parse_experiment("[geometry]\nkind = \"micrograin\"\ntau0 = " + std::to_string(tau0) +
                                                "\nbeta = 0.8\ntile = " + std::to_string(tile) + "\n" +
                                                run_section(tile == 40 ? 108 : 109, 32) + R"(
[[measure]]
quantity = "tau_plus"
theta_i_deg = [85]
samples = 50000
)", "test_simulate.toml");
      const std::vector<Table> ts = run(e, 2);
      v[k] = ts[0].value(0);
      se[k] = ts[0].stderr_of(0);
      ++k;
    }
    const double combined = std::hypot(se[0], se[1]);
    std::printf("[ info     ] tau+(85 deg), tau0 %.1f: tile 40 %.5f +- %.5f, tile 160 %.5f +- %.5f, z %.2f\n", tau0, v[0],
                se[0], v[1], se[1], (v[0] - v[1]) / combined);
    EXPECT_LT(std::fabs(v[0] - v[1]), 4 * combined) << "tau0 " << tau0;
  }
}

// SimulateOptions::keep_batch_values: each batch's estimates, in batch order,
// add up to the sums bit for bit; the sums are those of a run without them; and
// all of it is the same on 1, 2 and 3 threads. Micrograin tables (added a batch
// at a time) and slab BRDF tables (whose cells a batch adds one by one).
TEST(SimulateDeterminism, KeptBatchValuesAreTheBatchesAndChangeNothing) {
  const std::string slab = R"(
[geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.9
[run]
seed = 3
batches = 3
[[measure]]
quantity = "brdf"
theta_i_deg = [0, 60]
theta_o_bins = 4
phi_bins = 4
samples = 2000
)";
  for (const std::string& toml : {all_quantities(kIso, 5), slab}) {
    const Experiment e = parse_experiment(toml, "test_simulate.toml");
    const std::vector<Table> plain = run(e, 2);
    std::vector<std::vector<Table>> kept;
    for (int threads : {1, 2, 3}) {
      SimulateOptions o;
      o.threads = threads;
      o.quiet = true;
      o.keep_batch_values = true;
      kept.push_back(simulate(e, o));
    }
    ASSERT_EQ(plain.size(), kept[0].size());
    for (std::size_t k = 0; k < plain.size(); ++k) {
      const Table& t = kept[0][k];
      ASSERT_TRUE(t.has_batch_values()) << t.name;
      EXPECT_TRUE(bit_identical(t.sum, plain[k].sum)) << t.name;
      EXPECT_TRUE(bit_identical(t.sum_sq, plain[k].sum_sq)) << t.name;
      std::vector<double> sum(t.cells(), 0.0);
      for (std::int64_t b = 0; b < t.batches; ++b)
        for (std::size_t i = 0; i < t.cells(); ++i) sum[i] += t.batch_values[b * t.cells() + i];
      EXPECT_TRUE(bit_identical(sum, t.sum)) << t.name;
      for (std::size_t n = 1; n < kept.size(); ++n) {
        EXPECT_TRUE(bit_identical(kept[n][k].batch_values, t.batch_values)) << t.name << " on " << n + 1 << " threads";
        EXPECT_TRUE(bit_identical(kept[n][k].sum, t.sum)) << t.name;
      }
      EXPECT_FALSE(plain[k].has_batch_values()) << t.name;
    }
  }
}
