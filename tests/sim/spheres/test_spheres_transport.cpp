// Lambertian-sphere volumes, transport: the single-sphere phase histogram
// against Eq. 1, single scattering of the volumetric half-space against
// Eq. 10, energy at c = 1 (every path leaves through the top or the bottom
// with its full weight), bit-identical tables for 1 and 2 threads, and the
// dilute limit (Poisson f = 0.5 %) against the volumetric half-space.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "models/core/rng.h"
#include "models/core/statistics.h"
#include "sim/experiment/experiment.h"
#include "sim/experiment/simulate.h"
#include "sim/spheres/sphere_field.h"
#include "sim/spheres/walks.h"
#include "validate/metrics.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {

std::vector<Table> run(const std::string& text, int threads = 0) {
  const Experiment ex = parse_experiment(text, "test.toml");
  SimulateOptions o;
  o.quiet = true;
  o.threads = threads;
  return simulate(ex, o);
}

const Table& find(const std::vector<Table>& t, const std::string& name) {
  for (const Table& x : t)
    if (x.name == name) return x;
  throw std::runtime_error("no table " + name);
}

Verdict check_exact(const std::string& text, const std::string& table, const std::string& model) {
  const Experiment ex = parse_experiment(text, "test.toml");
  SimulateOptions o;
  o.quiet = true;
  const std::vector<Table> tables = simulate(ex, o);
  const Table& t = find(tables, table);
  const Comparison c = compare(t.values(), t.stderrs(), evaluate_model(model, t, ex), t.batches, {}, t.channels());
  return judge(c, true, 1e-3, 0);
}

}  // namespace

TEST(SpheresTransport, PhaseHistogramMatchesEq1) {
  const std::string text =
      "[geometry]\nkind = \"spheres\"\nalbedo = 0.5\nplacement = \"volumetric\"\n"
      "[run]\nseed = 21\nbatches = 8\n"
      "[[measure]]\nquantity = \"phase\"\nmu_bins = 32\nsamples = 100000\n";
  const Verdict v = check_exact(text, "phase", "phase_eq1");
  EXPECT_EQ(v.status, "pass") << v.reason;
}

TEST(SpheresTransport, VolumetricSingleScatteringMatchesEq10) {
  const std::string text =
      "[geometry]\nkind = \"spheres\"\nalbedo = [0.3, 0.8, 0.99]\nplacement = \"volumetric\"\n"
      "[run]\nseed = 22\nbatches = 8\n"
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0, 50, 75]\ntheta_o_bins = 6\nphi_bins = 6\n"
      "max_order = 1\nsamples = 100000\n";
  const Verdict v = check_exact(text, "brdf", "single_scattering_eq10");
  EXPECT_EQ(v.status, "pass") << v.reason;
}

TEST(SpheresTransport, EnergyIsConservedAtAlbedoOne) {
  // Every path must leave with weight exactly 1, through the top or the bottom.
  BrdfLayout l;
  l.theta_o_bins = 4;
  l.phi_bins = 4;
  l.order1_classes = {"sphere"};
  WalkSettings s;
  s.albedo = Rgb(1.0);
  s.depth_mfp = 10;
  SpherePacking p;
  p.volume_fraction = 0.07;
  p.tile = 20;
  p.depth_mfp = 10;
  Rng geometry(5);
  const SphereField field(place_poisson(p, geometry), p.tile);
  for (int packing = 0; packing < 2; ++packing) {
    std::vector<double> sums(l.sums_size(), 0.0);
    BrdfAccumulator acc(l, 0.0, sums);
    Rgb transmitted;
    Rng rng(99);
    const int paths = packing ? 20000 : 100000;
    const Vec3 wi = spherical_direction(0.7, 0.3);
    for (int i = 0; i < paths; ++i) {
      if (packing) packing_path(field, s, wi, rng, acc, transmitted);
      else volumetric_path(s, wi, rng, acc, transmitted);
    }
    double reflected = 0;
    for (int c = 0; c < l.components(); ++c) reflected += sums[l.binned_size() + c * 3];
    EXPECT_NEAR(reflected + transmitted[0], paths, 1e-9 * paths) << (packing ? "packing" : "volumetric");
    // A 10 mean-free-path conservative slab transmits ~ 4 / (3 (1 - g) (10 + 1.4)) ~ 8 %.
    EXPECT_GT(transmitted[0], 0.03 * paths);
    EXPECT_LT(transmitted[0], 0.20 * paths);
  }
}

// Every placement (packed, Poisson, the volumetric medium) on 1, 2 and 3
// threads: the same bits. 10^4 paths per direction: several chunks of 4096
// per table, added in a fixed order whatever thread ran them.
TEST(SpheresTransport, BitIdenticalForAnyThreadCountAndPlacement) {
  for (const char* placement : {"rsa", "poisson", "volumetric"}) {
    const std::string text =
        std::string("[geometry]\nkind = \"spheres\"\nalbedo = [0.3, 0.8, 0.95]\nvolume_fraction = 0.1\nplacement = \"") +
        placement + "\"\ntile = 20\ndepth_mfp = 15\n"
        "[run]\nseed = 3\nbatches = 2\n"
        "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0, 60]\ntheta_o_bins = 4\nphi_bins = 4\nsamples = 10000\n"
        "[[measure]]\nquantity = \"phase\"\nmu_bins = 8\nsamples = 10000\n";
    const std::vector<Table> a = run(text, 1);
    for (int threads : {2, 3}) {
      const std::vector<Table> b = run(text, threads);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].name, b[i].name);
        EXPECT_EQ(a[i].sum, b[i].sum) << placement << " " << a[i].name << " on " << threads << " threads";
        EXPECT_EQ(a[i].sum_sq, b[i].sum_sq) << placement << " " << a[i].name << " on " << threads << " threads";
      }
    }
  }
}

TEST(SpheresTransport, DiluteLimitMatchesVolumetric) {
  // Poisson spheres at f = 0.5 % against the volumetric half-space: a
  // two-sample test on the directional albedo per order and channel, and on
  // a coarse BRDF. The opposition (shadow-hiding) peak of the packing has an
  // angular width ~ r / mfp ~ 0.004 rad, far inside one bin.
  const std::string geometry =
      "[geometry]\nkind = \"spheres\"\nalbedo = [0.3, 0.8, 0.95]\nvolume_fraction = 0.005\ntile = 200\n"
      "transmission_threshold = 1e-3\n";
  const std::string measure =
      "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0, 60]\ntheta_o_bins = 4\nphi_bins = 4\n";
  const std::vector<Table> packing =
      run(geometry + "placement = \"poisson\"\n[run]\nseed = 1\nbatches = 6\n" + measure + "samples = 12000\n");
  const std::vector<Table> volume =
      run(geometry + "placement = \"volumetric\"\n[run]\nseed = 2\nbatches = 6\n" + measure + "samples = 60000\n");
  // Each cell's difference over its standard error is t-distributed (6 batches a side,
  // Welch's degrees of freedom), mapped to N(0, 1); per table and channel (the
  // channels share their paths), chi2 over the cells and the largest |z|, each at
  // 1e-3 after Šidák over the 6 (table, channel) pairs. A cell without an error
  // bar on either side (the same value in every batch) is not applicable if both
  // sides agree exactly, and a failure otherwise.
  const double alpha = sidak_per_test(1e-3, 6);
  for (const std::string name : {"brdf_albedo", "brdf"}) {
    const Table& p = find(packing, name);
    const Table& v = find(volume, name);
    const std::size_t channels = p.axes.back().size();
    std::vector<double> chi2(channels, 0.0), max_z(channels, 0.0);
    std::vector<int> cells(channels, 0);
    for (std::size_t i = 0; i < p.cells(); ++i) {
      const std::size_t k = i % channels;
      const double a = p.stderr_of(i), b = v.stderr_of(i);
      if (!(a > 0 || b > 0)) {
        EXPECT_EQ(p.value(i), v.value(i)) << name << " cell " << i << ": no error bar on either side";
        continue;
      }
      const double z = t_to_normal((p.value(i) - v.value(i)) / std::hypot(a, b), welch_dof(a, b, 6, 6));
      chi2[k] += z * z;
      max_z[k] = std::max(max_z[k], std::fabs(z));
      ++cells[k];
    }
    for (std::size_t k = 0; k < channels; ++k) {
      ASSERT_GT(cells[k], 0) << name << " channel " << k;
      EXPECT_GT(chi2_survival(chi2[k], cells[k]), alpha) << name << " channel " << k << ": chi2 " << chi2[k] << " over "
                                                          << cells[k] << " cells";
      EXPECT_LT(max_z[k], sidak_z_bound(alpha, cells[k])) << name << " channel " << k;
    }
  }
}

TEST(SpheresTransport, TransmissionStaysBelowTheThreshold) {
  // The depth chosen from transmission_threshold = 1e-3 must transmit less,
  // at normal and oblique incidence, from black to bright spheres: at low
  // albedo the unscattered light exp(-depth) dominates (it was 3.5x the
  // threshold at c = 0 when only diffusion set the depth). Seed 5, 4 batches
  // of 5e4 paths per direction: a violation shows as T - 3 stderr > 1e-3.
  for (const char* c : {"0", "0.3", "0.6", "0.64", "0.7", "0.9"}) {
    const std::vector<Table> t = run(std::string("[geometry]\nkind = \"spheres\"\nvolume_fraction = 0.07\n") +
                                     "transmission_threshold = 1e-3\nalbedo = " + c +
                                     "\n[run]\nseed = 5\nbatches = 4\n[[measure]]\nquantity = \"brdf\"\n"
                                     "theta_i_deg = [0, 60]\ntheta_o_bins = 2\nphi_bins = 2\nsamples = 50000\n");
    const Table& tr = find(t, "brdf_transmittance");
    for (std::size_t i = 0; i < tr.cells(); ++i)
      EXPECT_LT(tr.value(i) - 3 * tr.stderr_of(i), 1e-3) << "albedo " << c << ", cell " << i << ": T = " << tr.value(i);
  }
  // Where diffusion's decay length was shortest against the true one (c = 0.64,
  // T = 1.27e-4 at 1e-4 with the diffusion rule), at normal incidence in the
  // continuum (volumetric), 4 batches of 1e6 paths (stderr ~5e-6), seed 6.
  const std::vector<Table> t = run(
      "[geometry]\nkind = \"spheres\"\nplacement = \"volumetric\"\ntransmission_threshold = 1e-4\nalbedo = 0.64\n"
      "[run]\nseed = 6\nbatches = 4\n[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = 0\ntheta_o_bins = 2\n"
      "phi_bins = 2\nsamples = 1000000\n");
  const Table& tr = find(t, "brdf_transmittance");
  EXPECT_LT(tr.value(0) - 3 * tr.stderr_of(0), 1e-4) << "T = " << tr.value(0) << " +- " << tr.stderr_of(0);
  EXPECT_LT(tr.stderr_of(0), 1e-5);
}
