// tau_height: tau(i, h), the fraction of rays from i that hit a grain at
// unit-space height >= h (h = z / c in [0, 1]); equivalently the fraction of
// rays that meet the part of some grain above h, the filling factor at
// height h of the later papers: tau(i, h) = 1 - exp(-rho sigma(i, h)).
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator tau_height_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    std::vector<double> h(m.h_points);
    for (int k = 0; k < m.h_points; ++k) h[k] = static_cast<double>(k) / m.h_points;
    Table t(m.name, "tau_height",
            {theta_points("theta_i", m.theta_i), phi_points("phi_i", m.phi_i), Axis::points("h", "grain height c", h)});
    t.units = "1";
    t.description = "fraction of rays from i whose first hit is a grain at height >= h (h in units of c)";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const std::vector<double>& h = tables[0].axes[2].values;
    std::vector<double> est;
    std::uint64_t dir = 0;
    for (double theta : m.theta_i)
      for (double phi : m.phi_i) {
        const Vec3 d = -unit_direction(f, incident_direction(theta, phi));
        const Sums acc = run_chunks(m.samples, h.size(), key.with(dir++), [&](Rng& rng, std::uint64_t n, Sums& s) {
          for (std::uint64_t k = 0; k < n; ++k) {
            const Hit hit = f.intersect_unit(uniform_top_origin(f, rng), d);
            if (hit.kind != Hit::Kind::Grain) continue;
            const double z = hit.unit_normal.z;  // unit-space height of the hit point
            for (std::size_t j = 0; j < h.size() && h[j] <= z; ++j) s[j] += 1;
          }
        });
        for (double a : acc) est.push_back(a / static_cast<double>(m.samples));
      }
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
