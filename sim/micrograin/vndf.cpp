// vndf: the distribution of the normals at the first grain hit of rays from
// i (the visible NDF of the vNDF paper, Eq. 6/13), over (theta_m, phi_m - phi_i),
// normalised over grain hits: a density per steradian of real normals.
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator vndf_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment& ex) {
    const MicrograinGeometry& g = ex.micrograin;
    const bool folded = !g.anisotropic();
    Table t(m.name, "vndf",
            {theta_points("theta_i", m.theta_i), phi_points("phi_i", m.phi_i), theta_bins("theta_m", m.theta_m_bins),
             phi_bins("phi_m_rel", m.phi_m_bins, folded)});
    t.units = "1/sr";
    t.attributes["empty_cells"] = kEmptyCellsNote;
    t.description = "density of the normal at the first grain hit from i, per steradian, over grain hits (bin average)";
    t.attributes["phi_m_rel"] = folded ? "phi_m - phi_i folded into [0, pi] (isotropic field)" : "phi_m - phi_i in [0, 2pi)";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const Axis& th = tables[0].axes[2];
    const Axis& ph = tables[0].axes[3];
    const bool folded = !f.geometry().anisotropic();
    const std::size_t cells = th.size() * ph.size();
    std::vector<double> est;
    std::uint64_t dir = 0;
    for (double theta : m.theta_i)
      for (double phi : m.phi_i) {
        const Vec3 d = -unit_direction(f, incident_direction(theta, phi));
        const Sums acc = run_chunks(m.samples, cells + 1, key.with(dir++), [&](Rng& rng, std::uint64_t n, Sums& s) {
          for (std::uint64_t k = 0; k < n; ++k) {
            const Hit hit = f.intersect_unit(uniform_top_origin(f, rng), d);
            if (hit.kind != Hit::Kind::Grain) continue;
            s[cells] += 1;
            const int a = th.find_bin(spherical_theta(hit.normal));
            const int b = ph.find_bin(relative_azimuth(spherical_phi(hit.normal), phi, folded));
            if (a >= 0 && b >= 0) s[a * ph.size() + b] += 1;
          }
        });
        const double fold = folded ? 2.0 : 1.0;
        for (std::size_t a = 0; a < th.size(); ++a)
          for (std::size_t b = 0; b < ph.size(); ++b) {
            const double w = fold * cell_solid_angle(th.lower(a), th.upper(a), ph.lower(b), ph.upper(b));
            est.push_back(acc[cells] > 0 ? acc[a * ph.size() + b] / (acc[cells] * w) : NAN);
          }
      }
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
