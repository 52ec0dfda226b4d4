// ndf: the NDF D(m) of the grain surface, from rays at normal incidence
// (every point of the height field is seen), normalised over the
// grain-covered area (LRPB23 Eq. 14): integral of D(m) cos(theta_m) = 1.
// The stored value is the cosine-weighted bin average of D:
// P(m in bin | grain hit) / integral over the bin of cos(theta_m).
#include "sim/micrograin/estimator.h"
#include "sim/tally/polar_bins.h"

namespace mcref {

Estimator ndf_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    Table t(m.name, "ndf", {theta_bins("theta_m", m.theta_m_bins), phi_bins("phi_m", m.phi_m_bins, false)});
    t.units = "1/sr";
    t.attributes["empty_cells"] = kEmptyCellsNote;
    t.description = "NDF D(m), cosine-weighted bin average, normalised over the grain-covered area (Eq. 14)";
    return std::vector<Table>{t};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const Axis& th = tables[0].axes[0];
    const Axis& ph = tables[0].axes[1];
    const std::size_t cells = th.size() * ph.size();
    const Vec3 down = unit_direction(f, {0, 0, -1});
    const PolarBins theta_m(th);  // th.find_bin(spherical_theta(normal)), without acos
    const Sums acc = run_chunks(m.samples, cells + 1, key.with(0), [&](Rng& rng, std::uint64_t n, Sums& s) {
      // The chunk's rays, traced in packets (scratch kept per thread).
      thread_local std::vector<Vec3> origins, normals;
      thread_local std::vector<Hit::Kind> kinds;
      // Per cell, then one for the rays not counted; 64-bit, a type no other
      // datum in the loop has, so that stores to it cannot alias them.
      thread_local std::vector<std::uint64_t> count;
      uniform_top_origins(f, rng, n, origins);
      kinds.resize(n);
      normals.resize(n);
      f.first_hits_unit(origins.data(), n, down, kinds.data(), normals.data());
      count.assign(cells + 1, 0);
      std::uint64_t grains = 0;
      const std::size_t nphi = ph.size();
      std::uint64_t* tally = count.data();
      // Without branches on the (random) kind: a ray off the grains counts in count[cells].
      for (std::uint64_t k = 0; k < n; ++k) {
        const bool grain = kinds[k] == Hit::Kind::Grain;
        grains += grain;
        const int a = theta_m.bin(normals[k].z);
        int b = 0;
        if (nphi > 1 && grain) b = ph.find_bin(spherical_phi(normals[k]));
        const bool in = grain & (a >= 0) & (b >= 0);
        ++tally[in ? a * nphi + b : cells];
      }
      s[cells] += static_cast<double>(grains);
      for (std::size_t c = 0; c < cells; ++c) s[c] += static_cast<double>(count[c]);
    });
    std::vector<double> est(cells, 0.0);
    const double grain_hits = acc[cells];
    for (std::size_t a = 0; a < th.size(); ++a)
      for (std::size_t b = 0; b < ph.size(); ++b) {
        const double w = cell_projected_solid_angle(th.lower(a), th.upper(a), ph.lower(b), ph.upper(b));
        est[a * ph.size() + b] = grain_hits > 0 ? acc[a * ph.size() + b] / (grain_hits * w) : NAN;
      }
    tables[0].add_batch(est);
  };
  return e;
}

}  // namespace mcref
