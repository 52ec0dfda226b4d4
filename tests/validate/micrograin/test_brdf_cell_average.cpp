// The micrograin_brdf family's cell averages (issue #15, part 4) reach 1e-6
// relative (kCellRelTolerance; a cell below 1e-3 of the largest value tested
// for its model: 1e-9 of that value) against an independent reference: nested
// one-dimensional adaptive Gauss-Legendre (integrate_adaptive), outer in phi,
// inner in mu = cos theta_o split at cos theta_i, to 1e-9 of the cell (the
// cell rule under test integrates in theta_o, by 4 x 4 products checked
// against 3 x 3: validate/micrograin/brdf_cell_rule.h).
// Cells: the suite's tables (12 theta_o bins uniform in cos theta_o, 12 phi
// bins on [0, pi]) at theta_i = 80 and 89 deg: the grazing bin (85.2-90 deg)
// at backscatter (phi 0-15 deg) and mirror side (165-180 deg), the bin holding
// theta_i = 80 deg at backscatter (the union masking's cusp at o = i inside the
// cell's edge), and the albedo_curve table's grazing mirror-side cell
// (theta_o 60-90, phi 90-180 deg). Models: G_dist union and product, LRPB23,
// on diffuse grains (tau0 0.4, beta 1) and gold grains (tau0 0.9, beta 0.5,
// the specular lobe); the albedo's hemisphere integral at 89 deg.
// Deterministic: no random numbers. Each test also shows that the former
// fixed rules (3 x 3 Gauss-Legendre in (mu, phi) per cell, 24 x 24 over the
// hemisphere) miss the same tolerance somewhere, so it can fail.
// DISABLED (branch `cells`, issue #15 part 4 not finished): the references put
// nodes within ~1e-3 deg of grazing, where the union geometry costs ~70 ms a
// node; the first cell alone ran > 10 min, so the tests do not fit ctest's
// budget. Run them with --gtest_also_run_disabled_tests.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "models/core/quadrature.h"
#include "models/core/vec.h"
#include "sim/experiment/experiment.h"
#include "validate/micrograin/micrograin_brdf_value.h"
#include "validate/model_evaluation.h"

using namespace mcref;

namespace {

const double kDeg = kPi / 180;

Experiment experiment(bool gold, double tau0, double beta) {
  const std::string material = gold ? "[material.grain]\ntype = \"conductor\"\npreset = \"gold\"\n"
                                      "[material.base]\ntype = \"lambertian\"\nalbedo = 0.5\n"
                                    : "[material.grain]\ntype = \"lambertian\"\nalbedo = [0.18299, 0.67340, 0.42108]\n"
                                      "[material.base]\ntype = \"lambertian\"\nalbedo = 0.5\n";
  return parse_experiment("[geometry]\nkind = \"micrograin\"\ntau0 = " + std::to_string(tau0) +
                              "\nbeta = " + std::to_string(beta) + "\ntile = 20\n" + material +
                              "[[measure]]\nquantity = \"brdf\"\ntheta_i_deg = [0]\nsamples = 10\n",
                          "cells.toml");
}

// f mu of one model at (mu, phi), incidence (theta_i, 0), all channels, memoised
// (the channels share the nodes).
class Integrand {
 public:
  Integrand(std::string model, const Experiment& ex, double theta_i)
      : model_(std::move(model)), ex_(ex), wi_(spherical_direction(theta_i, 0)) {}
  double operator()(int k, double mu, double phi) {
    const auto key = std::make_pair(mu, phi);
    auto it = memo_.find(key);
    if (it == memo_.end()) {
      std::array<double, 3> v;
      micrograin_brdf_value(model_, ex_, wi_, spherical_direction(std::acos(std::fmin(1.0, mu)), phi), v.data());
      for (double& x : v) x *= mu;
      it = memo_.emplace(key, v).first;
    }
    return it->second[k];
  }

 private:
  std::string model_;
  const Experiment& ex_;
  Vec3 wi_;
  std::map<std::pair<double, double>, std::array<double, 3>> memo_;
};

// The former fixed rule: n x n Gauss-Legendre in (mu, phi).
double fixed_rule(Integrand& f, int k, double mu0, double mu1, double p0, double p1, int n) {
  const GaussLegendre g(n);
  double s = 0;
  for (std::size_t u = 0; u < g.x.size(); ++u)
    for (std::size_t v = 0; v < g.x.size(); ++v)
      s += g.w[u] * g.w[v] * f(k, 0.5 * (mu0 + mu1) + 0.5 * (mu1 - mu0) * g.x[u], 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * g.x[v]);
  return 0.25 * (mu1 - mu0) * (p1 - p0) * s;
}

// Reference ∫∫ f mu dmu dphi of channel k to about `tol` absolute: nested
// adaptive Gauss-Legendre, the mu integral split at mu_i = cos theta_i.
double reference(Integrand& f, int k, double mu_i, double mu0, double mu1, double p0, double p1, double tol) {
  auto inner = [&](double phi) {
    auto g = [&](double mu) { return f(k, mu, phi); };
    const double t = 0.1 * tol / (p1 - p0);
    if (mu_i <= mu0 || mu_i >= mu1) return integrate_adaptive(g, mu0, mu1, t);
    return integrate_adaptive(g, mu0, mu_i, 0.5 * t) + integrate_adaptive(g, mu_i, mu1, 0.5 * t);
  };
  return integrate_adaptive(inner, p0, p1, 0.5 * tol);
}

struct Cell {
  double theta_i, t0, t1, p0, p1;
};

void check_cells(const Experiment& ex, const std::vector<std::string>& models) {
  const double t_grazing = std::acos(1.0 / 12), t80_lo = std::acos(3.0 / 12), t80_hi = std::acos(2.0 / 12);
  const std::vector<Cell> cells{
      {80 * kDeg, t_grazing, kPi / 2, 0, kPi / 12},           {80 * kDeg, t_grazing, kPi / 2, 11 * kPi / 12, kPi},
      {80 * kDeg, t80_lo, t80_hi, 0, kPi / 12},               {89 * kDeg, t_grazing, kPi / 2, 0, kPi / 12},
      {89 * kDeg, t_grazing, kPi / 2, 11 * kPi / 12, kPi},    {89 * kDeg, kPi / 3, kPi / 2, kPi / 2, kPi}};
  int old_rule_misses = 0, n = 0;
  for (const std::string& model : models) {
    std::vector<std::array<double, 3>> got(cells.size()), ref(cells.size()), old(cells.size());
    double largest = 0;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const Cell& e = cells[c];
      const Table t("brdf", "brdf",
                    {Axis::points("theta_i", "rad", {e.theta_i}), Axis::points("phi_i", "rad", {0.0}),
                     Axis::bins("theta_o", "rad", {e.t0, e.t1}), Axis::bins("phi", "rad", {e.p0, e.p1}),
                     Axis::points("channel", "RGB index", {0, 1, 2})});
      const std::vector<double> v = evaluate_model(model, t, ex);
      Integrand f(model, ex, e.theta_i);
      const double mu0 = std::cos(e.t1), mu1 = std::cos(e.t0);
      const double den = 0.5 * (mu1 * mu1 - mu0 * mu0) * (e.p1 - e.p0);
      for (int k = 0; k < 3; ++k) {
        const double rough = std::fabs(fixed_rule(f, k, mu0, mu1, e.p0, e.p1, 8)) + 1e-300;
        ref[c][k] = reference(f, k, std::cos(e.theta_i), mu0, mu1, e.p0, e.p1, 1e-9 * rough) / den;
        got[c][k] = v[static_cast<std::size_t>(k)];
        old[c][k] = fixed_rule(f, k, mu0, mu1, e.p0, e.p1, 3) / den;
        largest = std::fmax(largest, std::fabs(ref[c][k]));
      }
    }
    for (std::size_t c = 0; c < cells.size(); ++c)
      for (int k = 0; k < 3; ++k) {
        const double r = ref[c][k];
        const double tol = std::fabs(r) < 1e-3 * largest ? 1e-9 * largest : kCellRelTolerance * std::fabs(r);
        EXPECT_NEAR(got[c][k], r, tol) << model << " theta_i " << cells[c].theta_i / kDeg << " cell theta_o ("
                                       << cells[c].t0 / kDeg << ", " << cells[c].t1 / kDeg << ") phi ("
                                       << cells[c].p0 / kDeg << ", " << cells[c].p1 / kDeg << ") channel " << k;
        if (std::fabs(old[c][k] - r) > tol) ++old_rule_misses;
        ++n;
      }
  }
  EXPECT_GT(old_rule_misses, 0) << "the former 3 x 3 rule meets the tolerance on all " << n << " cells";
}

TEST(BrdfCellAverage, DISABLED_DiffuseGrainsUnionProductAndLrpb23) {
  check_cells(experiment(false, 0.4, 1.0), {"gdist_total_union", "gdist_total", "lrpb23_quadrature"});
}

TEST(BrdfCellAverage, DISABLED_GoldGrainsSpecularLobe) {
  check_cells(experiment(true, 0.9, 0.5), {"gdist_grain_union", "lrpb23_grain_quadrature"});
}

// The albedo table's grain and base components at theta_i = 89 deg: the
// hemisphere, phi in [0, pi] twice.
TEST(BrdfCellAverage, DISABLED_AlbedoHemisphere) {
  const Experiment ex = experiment(false, 0.4, 1.0);
  const double theta_i = 89 * kDeg;
  const Table t("brdf_albedo", "albedo",
                {Axis::points("theta_i", "rad", {theta_i}), Axis::points("phi_i", "rad", {0.0}),
                 Axis::points("component", "index", {0, 1, 2}), Axis::points("channel", "RGB index", {0, 1, 2})});
  const std::vector<double> v = evaluate_model("gdist_albedo_union", t, ex);
  const std::array<std::string, 2> parts{"gdist_grain_union", "gdist_base_union"};
  int old_rule_misses = 0;
  for (std::size_t part = 0; part < 2; ++part) {
    Integrand f(parts[part], ex, theta_i);
    for (int k = 0; k < 3; ++k) {
      const double rough = std::fabs(fixed_rule(f, k, 0, 1, 0, kPi, 8)) + 1e-300;
      const double ref = 2 * reference(f, k, std::cos(theta_i), 0, 1, 0, kPi, 1e-9 * rough);
      const double got = v[t.index({0, 0, part, static_cast<std::size_t>(k)})];
      const double tol = kCellRelTolerance * std::fabs(ref);
      EXPECT_NEAR(got, ref, tol) << parts[part] << " channel " << k;
      if (std::fabs(2 * fixed_rule(f, k, 0, 1, 0, kPi, 24) - ref) > tol) ++old_rule_misses;
    }
  }
  EXPECT_GT(old_rule_misses, 0) << "the former 24 x 24 rule meets the tolerance everywhere";
}

}  // namespace
