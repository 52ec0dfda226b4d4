// phi_conditional: the histogram of the azimuth phi' that the vNDF sampler's
// triangle cut draws given theta' (vNDF paper Sec. 4.2, Listing 3; the
// paper's Fig. 5), in the unit space, relative to the azimuth of i'. No ray
// is traced: the table checks the sampler itself against the conditional
// density of phi (Eq. 26) and shows its tent approximation (Eq. 28).
// phi' is binned over u = phi / phi_q in [-1, 1] (phi_q the visibility bound,
// pi without shadow), so that every configuration fills every bin; the value
// is a density per radian of phi (count / (samples du phi_q)).
#include <cmath>

#include "models/micrograin/phi_conditional.h"
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator phi_conditional_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    Table t(m.name, "phi_conditional",
            {theta_points("theta_i", m.theta_i), theta_points("theta_m", m.theta_m),
             Axis::uniform_bins("phi_over_phi_q", "1", -1.0, 1.0, m.phi_bins)});
    t.units = "1/rad";
    t.description = "density per radian of the azimuth phi' - phi_i' drawn by the vNDF sampler's triangle cut given "
                    "theta' (unit space; bin average)";
    t.attributes["angles"] = "unit-space theta_i' and theta_m' (the conditional does not depend on tau0 or beta)";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField&, const Experiment&, const Measure& m, const StreamKey& key,
                   std::vector<Table>& tables) {
    const Axis& u = tables[0].axes[2];
    std::vector<double> est;
    std::uint64_t config = 0;
    for (double theta_i : m.theta_i)
      for (double theta_m : m.theta_m) {
        const micrograin::PhiConditional p(std::cos(theta_i), std::sin(theta_i), std::cos(theta_m),
                                           std::sin(theta_m));
        const Sums acc = run_chunks(m.samples, u.size(), key.with(config++), [&](Rng& rng, std::uint64_t n, Sums& s) {
          for (std::uint64_t k = 0; k < n; ++k) {
            const double u_s = rng.uniform(), u_t = rng.uniform();
            const double x = p.sample(u_s, u_t).phi / p.phi_q;  // in [-1, 1]
            const int b = u.find_bin(std::fmin(x, 0x1.fffffffffffffp-1));  // phi = phi_q: the last bin
            if (b >= 0) s[b] += 1;
          }
        });
        for (std::size_t b = 0; b < u.size(); ++b)
          est.push_back(acc[b] / (static_cast<double>(m.samples) * (u.upper(b) - u.lower(b)) * p.phi_q));
      }
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
