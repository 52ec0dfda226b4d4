// Lambertian-sphere volumes (issue #5): for each realization, place the
// spheres from the realization's own seed and build the field (explicit
// placements only), then add one batch to every measure's tables.
#include <memory>

#include "models/core/rng.h"
#include "sim/experiment/simulate_kinds.h"
#include "sim/spheres/sphere_estimators.h"
#include "sim/spheres/sphere_field.h"

namespace mcref {

BatchLoop::Tables sphere_tables(const Experiment& ex) {
  BatchLoop::Tables tables;
  for (const Measure& m : ex.measures)
    tables.push_back(m.quantity == "phase" ? make_phase_tables(m, ex) : make_sphere_brdf_tables(m, ex));
  return tables;
}

std::vector<Table> simulate_spheres(const Experiment& ex, const BatchLoop& loop) {
  BatchLoop::Tables tables = sphere_tables(ex);
  bool needs_field = false;
  for (const Measure& m : ex.measures)
    needs_field = needs_field || (m.quantity != "phase" && ex.spheres.placement != SpherePlacement::volumetric);
  loop.run(ex.run.batches, tables, [&](int b, BatchLoop::Tables& into) {
    std::unique_ptr<SphereField> field;
    if (needs_field) {
      Rng rng(stream_seed({ex.run.seed, static_cast<std::uint64_t>(b), kGeometryStream}));
      field = std::make_unique<SphereField>(place_spheres(ex.spheres, rng), ex.spheres.tile);
    }
    for (std::size_t k = 0; k < ex.measures.size(); ++k) {
      const Measure& m = ex.measures[k];
      const StreamKey key{ex.run.seed, static_cast<std::uint64_t>(b), k};
      if (m.quantity == "phase") add_phase_batch(ex, m, key, into[k]);
      else add_sphere_brdf_batch(field.get(), ex, m, key, into[k]);
      loop.progress().advance(work_units(m));
    }
  });
  return flatten(std::move(tables));
}

}  // namespace mcref
