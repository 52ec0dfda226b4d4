// tau_plus: the visible filling factor tau+(i) (LRPB23 Eq. 22, Fig. 9): the
// fraction of rays from direction i whose first hit is a grain.
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator tau_plus_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    Table t(m.name, "tau_plus", {theta_points("theta_i", m.theta_i), phi_points("phi_i", m.phi_i)});
    t.units = "1";
    t.description = "visible filling factor: fraction of rays from i whose first hit is a grain";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    std::vector<double> est;
    std::uint64_t dir = 0;
    for (double theta : m.theta_i)
      for (double phi : m.phi_i) {
        const Vec3 d = -unit_direction(f, incident_direction(theta, phi));
        const Sums acc = run_chunks(m.samples, 1, key.with(dir++), [&](Rng& rng, std::uint64_t n, Sums& s) {
          // The chunk's rays, traced in packets (scratch kept per thread).
          thread_local std::vector<Vec3> origins;
          thread_local std::vector<Hit::Kind> kinds;
          uniform_top_origins(f, rng, n, origins);
          kinds.resize(n);
          f.first_hits_unit(origins.data(), n, d, kinds.data());
          std::uint64_t grains = 0;
          for (Hit::Kind k : kinds) grains += k == Hit::Kind::Grain;
          s[0] += static_cast<double>(grains);
        });
        est.push_back(acc[0] / static_cast<double>(m.samples));
      }
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
