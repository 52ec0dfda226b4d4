// brdf on Lambertian-sphere volumes: explicit packings and the volumetric half-space.
#include <cstdio>
#include <stdexcept>

#include "sim/spheres/derived_tables.h"
#include "sim/spheres/sphere_estimators.h"
#include "sim/spheres/sphere_field.h"
#include "sim/spheres/walks.h"
#include "sim/tally/brdf_batch.h"

namespace mcref {

BrdfLayout sphere_brdf_layout(const Measure& m, const Experiment& ex) {
  BrdfLayout l;
  // (The derived mode table needs the folded azimuth: ex.isotropic, always set for spheres.)
  l.theta_o_bins = m.theta_o_bins;
  l.phi_bins = m.phi_bins;
  l.folded = ex.isotropic;
  l.transmission = false;
  l.order1_classes = {"sphere"};
  return l;
}

std::vector<Table> make_sphere_brdf_tables(const Measure& m, const Experiment& ex) {
  const BrdfLayout l = sphere_brdf_layout(m, ex);
  std::vector<Table> t = make_brdf_tables(m.name, m.theta_i, m.phi_i, l);
  const SpherePacking& p = ex.spheres;
  Table tr(m.name + "_transmittance", "transmittance",
           {Axis::points("theta_i", "rad", m.theta_i), Axis::points("phi_i", "rad", m.phi_i),
            Axis::points("channel", "RGB index", {0, 1, 2})});
  tr.units = "1";
  tr.description = "energy leaving through the bottom of the slab per unit incident energy";
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.6g", p.depth_in_mfp());
  tr.attributes["depth_mfp"] = buf;
  std::snprintf(buf, sizeof buf, "%.6g", p.depth() * p.radius);
  tr.attributes["depth"] = buf;
  std::snprintf(buf, sizeof buf, "%.3g", p.transmission_threshold);
  tr.attributes["transmission_threshold"] = buf;
  tr.attributes["placement"] = placement_name(p.placement);
  t.push_back(tr);
  // Derived per batch (sim/spheres/derived_tables.h), volumetric half-space only:
  // the Fourier modes of the total BRDF, and k_d when theta_i are Gauss-Legendre nodes.
  if (p.placement == SpherePlacement::volumetric && l.folded) {
    t.push_back(make_mode_table(t[0]));
    if (!spherical_albedo_weights(m.theta_i).empty())
      for (const Table& x : std::vector<Table>(t))
        if (x.name == m.name + "_albedo") t.push_back(make_kd_table(x));
  }
  for (Table& x : t) {
    x.attributes["placement"] = placement_name(p.placement);
    if (p.placement == SpherePlacement::volumetric) continue;  // a continuum has no volume fraction
    std::snprintf(buf, sizeof buf, "%.6g", p.volume_fraction);
    x.attributes["volume_fraction"] = buf;
  }
  return t;
}

void add_sphere_brdf_batch(const SphereField* field, const Experiment& ex, const Measure& m, const StreamKey& key,
                           std::vector<Table>& tables) {
  const BrdfLayout l = sphere_brdf_layout(m, ex);
  WalkSettings s;
  s.albedo = ex.spheres.albedo;
  s.max_order = m.max_order;
  s.depth_mfp = ex.spheres.depth_in_mfp();
  const std::size_t size = l.sums_size() + 3;
  std::vector<std::vector<double>> sums;
  std::vector<double> transmitted;
  std::uint64_t direction = 0;
  for (double ti : m.theta_i)
    for (double pi : m.phi_i) {
      const Vec3 wi = spherical_direction(ti, pi);
      Sums total = run_chunks(static_cast<std::uint64_t>(m.samples), size, key.with(direction++),
                              [&](Rng& rng, std::uint64_t count, Sums& out) {
                                BrdfAccumulator acc(l, pi, out);
                                Rgb tr;
                                for (std::uint64_t i = 0; i < count; ++i) {
                                  if (field) packing_path(*field, s, wi, rng, acc, tr);
                                  else volumetric_path(s, wi, rng, acc, tr);
                                }
                                for (int k = 0; k < 3; ++k) out[l.sums_size() + k] += tr[k];
                              });
      for (int k = 0; k < 3; ++k) transmitted.push_back(total[l.sums_size() + k] / static_cast<double>(m.samples));
      total.resize(l.sums_size());
      sums.push_back(std::move(total));
    }
  // One batch of the brdf tables, kept apart so that the derived tables see it.
  std::vector<Table> batch = make_brdf_tables(m.name, m.theta_i, m.phi_i, l);
  add_brdf_batch(sums, static_cast<double>(m.samples), l, batch);
  const Table *total = nullptr, *albedo = nullptr;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    if (tables[i].name != batch[i].name) throw std::logic_error("sphere brdf tables out of order");
    tables[i].add_batch(batch[i].values());
    if (batch[i].name == m.name) total = &batch[i];
    if (batch[i].name == m.name + "_albedo") albedo = &batch[i];
  }
  for (std::size_t i = batch.size(); i < tables.size(); ++i) {
    Table& t = tables[i];
    if (t.name == m.name + "_transmittance") t.add_batch(transmitted);
    else if (t.name == m.name + "_modes") t.add_batch(mode_estimate(*total, total->values(), t));
    else if (t.name == m.name + "_kd") t.add_batch(kd_estimate(*albedo, albedo->values(), spherical_albedo_weights(m.theta_i)));
  }
}

}  // namespace mcref
