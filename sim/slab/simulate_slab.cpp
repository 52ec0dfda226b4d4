// Microflake slabs (issue #4): run.batches independent batches of paths per
// measure and incident direction through one SlabMedium (the slab has no
// random geometry), binned by the shared BRDF tally (reflection, and
// transmission when there is no substrate), split by order with the order-1
// classes volume / substrate.
// For conservative stacks without a substrate and without a depth cap, one
// more table <name>_energy (quantity "energy_balance") holds the scattered
// energy, reflectance + transmittance without the unscattered (delta) part,
// per incident direction: the white furnace test, R + T_scattered = 1 - T_delta.
// (An analog walk conserves weight exactly, so R + T including the delta lobe
// would be 1 with zero variance: nothing to test statistically.)
#include "sim/experiment/simulate_kinds.h"

#include <stdexcept>
#include <string>

#include "sim/parallel/run_chunks.h"
#include "sim/slab/escape.h"
#include "sim/slab/free_flight.h"
#include "sim/slab/medium.h"
#include "sim/slab/walk.h"
#include "sim/slab/wave_walk.h"
#include "sim/tally/brdf_batch.h"

namespace mcref {

namespace {

BrdfLayout slab_layout(const Measure& m, const Experiment& ex) {
  BrdfLayout l;
  l.theta_o_bins = m.theta_o_bins;
  l.phi_bins = m.phi_bins;
  l.folded = ex.isotropic;
  l.transmission = ex.slab.substrate.kind == SlabSubstrate::Kind::kNone;
  l.order1_classes = {"volume", "substrate"};
  return l;
}

bool writes_energy_table(const Measure& m, const Experiment& ex) {
  return ex.slab.conservative() && m.max_order == 0 && ex.slab.substrate.kind == SlabSubstrate::Kind::kNone;
}

Table energy_table(const Measure& m) {
  Table t(m.name + "_energy", "energy_balance",
          {Axis::points("theta_i", "rad", m.theta_i), Axis::points("phi_i", "rad", m.phi_i),
           Axis::points("channel", "RGB index", {0, 1, 2})});
  t.units = "1";
  t.description = "scattered energy: reflectance + transmittance, all orders, without the unscattered delta transmission "
                  "(conservative stack: equals 1 - exp(-sum tau_k sigma_k(wi) / mu_i))";
  return t;
}

}  // namespace

BatchLoop::Tables slab_tables(const Experiment& ex, const std::vector<std::string>& keep) {
  BatchLoop::Tables tables;
  for (const Measure& m : ex.measures) {
    tables.push_back(make_brdf_tables(m.name, m.theta_i, m.phi_i, slab_layout(m, ex), keep));
    if (writes_energy_table(m, ex)) tables.back().push_back(energy_table(m));
  }
  return tables;
}

std::vector<Table> simulate_slab(const Experiment& ex, const BatchLoop& loop, const std::vector<std::string>& keep) {
  const volume::SlabMedium medium(ex.slab);
  if (ex.slab.estimator != SlabEstimator::kAnalog)
    if (const std::string why = volume::escape_unsupported(medium); !why.empty()) throw std::invalid_argument(why);
  BatchLoop::Tables tables = slab_tables(ex, keep);
  loop.run(ex.run.batches, tables, [&](int b, BatchLoop::Tables& into) {
    for (std::size_t k = 0; k < ex.measures.size(); ++k) {
      const Measure& m = ex.measures[k];
      const BrdfLayout layout = slab_layout(m, ex);
      volume::WalkSettings ws;
      ws.max_order = m.max_order;
      ws.delta_transmission = ex.slab.delta_transmission;
      ws.estimator = ex.slab.estimator;
      const StreamKey key{ex.run.seed, static_cast<std::uint64_t>(b), k};
      BrdfBatch batch(layout, static_cast<double>(m.samples), into[k]);
      std::vector<double> energy;
      for (std::size_t i = 0; i < m.theta_i.size(); ++i)
        for (std::size_t j = 0; j < m.phi_i.size(); ++j) {
          const double phi_i = m.phi_i[j];
          const Vec3 wi = spherical_direction(m.theta_i[i], phi_i);
          const std::size_t direction = i * m.phi_i.size() + j;
          const Sums sums = run_chunks(static_cast<std::uint64_t>(m.samples), layout.sums_size(), key.with(direction),
                                    [&](Rng& rng, std::uint64_t count, Sums& s) {
                                      BrdfAccumulator acc(layout, phi_i, s);
                                      if (ex.slab.wave_walk) {
                                        volume::wave_walk(medium, ws, wi, count, rng, acc);
                                        return;
                                      }
                                      auto flight = volume::make_flight(medium);
                                      for (std::uint64_t n = 0; n < count; ++n)
                                        volume::walk(medium, *flight, ws, wi, rng, acc);
                                    });
          batch.add(direction, sums);
          if (writes_energy_table(m, ex)) {
            double e[3] = {0, 0, 0};
            // Non-delta energies of every component and hemisphere (no substrate: the
            // only delta lobe is the unscattered transmission).
            const std::size_t first = layout.binned_size(), n = static_cast<std::size_t>(layout.components()) * layout.hemispheres() * 3;
            for (std::size_t q = 0; q < n; ++q) e[q % 3] += sums[first + q];
            for (double x : e) energy.push_back(x / static_cast<double>(m.samples));
          }
        }
      batch.close();
      if (writes_energy_table(m, ex)) into[k].back().add_batch(energy);
      loop.progress().advance(work_units(m));
    }
  });
  return flatten(std::move(tables));
}

}  // namespace mcref
