// pore_visibility: V_p(i, o), the probability that a point of the base plane
// lying in a pore (under no grain) is visible from both i and o, over
// (theta_i, theta_o, phi = phi_o - phi_i). Beside it, the product
// V_p(i) V_p(o) that assumes independent visibilities, which is what LRPB23
// Eq. 23/24 use: 1 - w+(i, o) = (1 - tau0) V_p(i) V_p(o).
#include <sstream>

#include "sim/micrograin/estimator.h"

namespace mcref {

Estimator pore_visibility_estimator() {
  Estimator e;
  e.make_tables = [](const Measure& m, const Experiment&) {
    std::vector<Axis> axes{theta_points("theta_i", m.theta_i), theta_points("theta_o", m.theta_o), phi_points("phi", m.phi)};
    Table joint(m.name, "pore_visibility", axes);
    joint.units = "1";
    joint.attributes["empty_cells"] = kEmptyCellsNote;
    joint.description = "P(pore point visible from i and from o | base point in a pore)";
    joint.attributes["phi"] = "relative azimuth phi_o - phi_i; 0 = back toward the light";
    std::ostringstream phi_i;
    phi_i.precision(17);
    phi_i << m.phi_i.front();
    joint.attributes["phi_i"] = phi_i.str();  // azimuth of i (rad)
    Table product(m.name + "_independent", "pore_visibility_independent", axes);
    product.units = "1";
    product.attributes["empty_cells"] = kEmptyCellsNote;
    product.attributes = joint.attributes;
    product.description = "P(visible from i | pore) * P(visible from o | pore), per batch (the independence assumption of Eq. 23)";
    return std::vector<Table>{joint, product};
  };
  e.add_batch = [](const MicrograinField& f, const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
    const double phi_i = m.phi_i.front();
    // Distinct directions: the incident ones, then (theta_o, phi) pairs.
    std::vector<Vec3> dirs;
    for (double ti : m.theta_i) dirs.push_back(unit_direction(f, incident_direction(ti, phi_i)));
    for (double to : m.theta_o)
      for (double p : m.phi) dirs.push_back(unit_direction(f, incident_direction(to, phi_i + p)));
    const std::size_t ni = m.theta_i.size(), no = m.theta_o.size(), np = m.phi.size();
    const std::size_t cells = ni * no * np;
    // sums: [0] pore points, [1 .. dirs] visible per direction, then joint per cell.
    const Sums acc = run_chunks(m.samples, 1 + dirs.size() + cells, key.with(0), [&](Rng& rng, std::uint64_t n, Sums& s) {
      std::vector<char> vis(dirs.size());
      for (std::uint64_t k = 0; k < n; ++k) {
        const Vec3 p{rng.uniform() * f.unit_side_x(), rng.uniform() * f.unit_side_y(), 0.0};
        if (f.under_grain(p.x, p.y)) continue;  // under a grain: not a pore
        s[0] += 1;
        for (std::size_t d = 0; d < dirs.size(); ++d) {
          vis[d] = !f.occluded_unit(p, dirs[d], MicrograinField::kNoGrain);
          s[1 + d] += vis[d];
        }
        for (std::size_t a = 0; a < ni; ++a)
          for (std::size_t b = 0; b < no; ++b)
            for (std::size_t c = 0; c < np; ++c)
              s[1 + dirs.size() + (a * no + b) * np + c] += vis[a] && vis[ni + b * np + c];
      }
    });
    std::vector<double> joint(cells), product(cells);
    const double pores = acc[0];
    for (std::size_t a = 0; a < ni; ++a)
      for (std::size_t b = 0; b < no; ++b)
        for (std::size_t c = 0; c < np; ++c) {
          const std::size_t cell = (a * no + b) * np + c;
          joint[cell] = pores > 0 ? acc[1 + dirs.size() + cell] / pores : NAN;
          product[cell] = pores > 0 ? (acc[1 + a] / pores) * (acc[1 + ni + b * np + c] / pores) : NAN;
        }
    tables[0].add_batch(joint);
    tables[1].add_batch(product);
  };
  return e;
}

}  // namespace mcref
