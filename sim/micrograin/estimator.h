#pragma once
// What every micrograin estimator shares: the measure it serves, the field of
// the current realization (sampled with sim/parallel/run_chunks.h), and small
// helpers for directions and bins.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/experiment/experiment.h"
#include "sim/micrograin/micrograin_field.h"
#include "sim/parallel/run_chunks.h"
#include "sim/tally/table.h"

namespace mcref {

// A micrograin estimator creates its (empty) tables from the measure, and
// adds one batch to each of them per realization of the field.
struct Estimator {
  std::function<std::vector<Table>(const Measure&, const Experiment&)> make_tables;
  std::function<void(const MicrograinField&, const Experiment&, const Measure&, const StreamKey&, std::vector<Table>&)>
      add_batch;
};
const Estimator& estimator_for(const std::string& quantity);

// The real-space incident direction (pointing away from the surface).
inline Vec3 incident_direction(double theta, double phi) { return spherical_direction(theta, phi); }
// The unit-space image of a real direction (same ray parameter t).
inline Vec3 unit_direction(const MicrograinField& f, Vec3 d) {
  const MicrograinGeometry& g = f.geometry();
  return {d.x / g.r_x(), d.y / g.r_y(), d.z / g.c()};
}
// A unit-space ray origin uniform over the tile, at the top of the grains.
inline Vec3 uniform_top_origin(const MicrograinField& f, Rng& rng) {
  return {rng.uniform() * f.unit_side_x(), rng.uniform() * f.unit_side_y(), 1.0};
}

// n such origins, drawn in order (two uniforms each) into `out`.
inline void uniform_top_origins(const MicrograinField& f, Rng& rng, std::size_t n, std::vector<Vec3>& out) {
  out.resize(n);
  for (Vec3& o : out) o = uniform_top_origin(f, rng);
}

// Axes shared by the estimators.
Axis theta_points(const std::string& name, const std::vector<double>& v);
Axis phi_points(const std::string& name, const std::vector<double>& v);
// theta in [0, pi/2) in `n` bins; relative azimuth over [0, pi] if folded
// (isotropic fields: the statistics are symmetric in +-phi), else [0, 2pi).
Axis theta_bins(const std::string& name, int n);
Axis phi_bins(const std::string& name, int n, bool folded);
// Solid angle and cosine-weighted solid angle of a (theta, phi) cell.
double cell_solid_angle(double t0, double t1, double p0, double p1);
double cell_projected_solid_angle(double t0, double t1, double p0, double p1);

}  // namespace mcref
