// g1: masking of the grain height field.
// Points of the height field (grain surface not buried in another grain) are
// sampled in proportion to their projected area toward i: a uniform grain, a
// uniform point of its projected disc along i, the entry point of that line
// into the grain; kept if on the upper half and not inside another grain.
// (a) g1: the fraction of them unoccluded toward i = visible projected grain
//     area / projected area of the height field's grain surface facing i.
// (b) g1_conditional: the same fraction per bin of the real normal m, over
//     (theta_m, phi_m - phi_i).
#include "models/core/frame.h"
#include "models/core/warp.h"
#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator g1_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment& ex) {
    const MicrograinGeometry& g = ex.micrograin;
    const bool folded = !g.anisotropic();
    Table marginal(m.name, "g1", {theta_points("theta_i", m.theta_i), phi_points("phi_i", m.phi_i)});
    marginal.units = "1";
    marginal.attributes["empty_cells"] = kEmptyCellsNote;
    marginal.description = "G1(i): visible projected grain area toward i / projected area of the height field's grain surface facing i";
    Table conditional(m.name + "_conditional", "g1_conditional",
                      {theta_points("theta_i", m.theta_i), phi_points("phi_i", m.phi_i),
                       theta_bins("theta_m", m.theta_m_bins), phi_bins("phi_m_rel", m.phi_m_bins, folded)});
    conditional.units = "1";
    conditional.description = "G1(i, m): fraction of height-field points with normal m (sampled by projected area toward i) unoccluded toward i";
    conditional.attributes["empty_cells"] = kEmptyCellsNote;
    return std::vector<Table>{marginal, conditional};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const Axis& th = tables[1].axes[2];
    const Axis& ph = tables[1].axes[3];
    const bool folded = !f.geometry().anisotropic();
    const std::size_t cells = th.size() * ph.size();
    std::vector<double> marginal, conditional;
    std::uint64_t dir = 0;
    for (double theta : m.theta_i)
      for (double phi : m.phi_i) {
        const Vec3 toward_i = normalize(unit_direction(f, incident_direction(theta, phi)));
        const Frame frame(toward_i);
        // sums: [0] accepted, [1] visible, then per cell: accepted, visible.
        const Sums acc = run_chunks(m.samples, 2 + 2 * cells, key.with(dir++), [&](Rng& rng, std::uint64_t n, Sums& s) {
          for (std::uint64_t k = 0; k < n; ++k) {
            if (f.grain_count() == 0) return;
            const std::size_t grain = rng.below(f.grain_count());
            const Vec3 c = f.unit_centre(grain);
            double u, v;
            sample_uniform_disc(rng.uniform(), rng.uniform(), u, v);
            // Entry point of the line through the disc point along -i into the unit sphere.
            const double w = std::sqrt(std::fmax(0.0, 1.0 - u * u - v * v));
            const Vec3 local = frame.s * u + frame.t * v + toward_i * w;
            const Vec3 p = c + local;
            if (p.z < 0) continue;                        // the lower half is not grain surface
            if (f.inside_other_grain(p, grain)) continue;  // buried: not on the height field
            const bool visible = !f.occluded_unit(p, toward_i, static_cast<std::uint32_t>(grain));
            s[0] += 1;
            s[1] += visible;
            const Vec3 normal = f.normal_from_unit(local);
            const int a = th.find_bin(spherical_theta(normal));
            const int b = ph.find_bin(relative_azimuth(spherical_phi(normal), phi, folded));
            if (a >= 0 && b >= 0) {
              s[2 + 2 * (a * ph.size() + b)] += 1;
              s[3 + 2 * (a * ph.size() + b)] += visible;
            }
          }
        });
        marginal.push_back(acc[0] > 0 ? acc[1] / acc[0] : NAN);
        for (std::size_t c = 0; c < cells; ++c)
          conditional.push_back(acc[2 + 2 * c] > 0 ? acc[3 + 2 * c] / acc[2 + 2 * c] : NAN);
      }
    tables[0].add_batch(marginal);
    tables[1].add_batch(conditional);
  };
  return e;
}

}  // namespace mcref
