// phase: parallel rays on one Lambertian sphere, one bounce, histogram of the
// deflection cosine mu = d_in . d_out (d'Eon 2021, Eq. 1 derived from geometry).
#include "models/core/frame.h"
#include "models/core/warp.h"
#include "sim/spheres/sphere_estimators.h"
#include "sim/spheres/sphere_field.h"

namespace mcref {

std::vector<Table> make_phase_tables(const Measure& m, const Experiment&) {
  Table t(m.name, "phase", {Axis::uniform_bins("mu", "1", -1.0, 1.0, m.mu_bins)});
  t.units = "1";
  t.description =
      "density of the deflection cosine mu (propagation in . propagation out) of light reflected once by a "
      "Lambertian sphere under parallel illumination, per reflected ray (albedo excluded); 2 pi p(mu) of Eq. 1";
  return {t};
}

void add_phase_batch(const Experiment&, const Measure& m, const StreamKey& key, std::vector<Table>& tables) {
  // One unit sphere in the middle of a tile wide enough that nothing wraps onto it.
  const Vec3 centre{4, 4, 0};
  const SphereField field({centre}, 8.0);
  const int n = m.mu_bins;
  // Sums: one count per bin, then the rays that missed (must stay 0).
  Sums s = run_chunks(static_cast<std::uint64_t>(m.samples), n + 1, key.with(0), [&](Rng& rng, std::uint64_t count,
                                                                                       Sums& out) {
    for (std::uint64_t i = 0; i < count; ++i) {
      // A random direction of the parallel beam, and a point uniform on the
      // sphere's projected disc, two radii in front of it.
      const Vec3 d = -sample_uniform_sphere(rng.uniform(), rng.uniform());
      double x, y;
      sample_uniform_disc(rng.uniform(), rng.uniform(), x, y);
      const Frame f(d);
      const Vec3 o = centre - d * 2.0 + f.s * x + f.t * y;
      const SphereHit h = field.trace(o, d);
      if (h.kind != SphereHit::Kind::Sphere) {
        out[n] += 1;
        continue;
      }
      const Vec3 out_dir = Frame(h.normal).to_world(sample_cosine_hemisphere(rng.uniform(), rng.uniform()));
      const double mu = dot(d, out_dir);
      const int b = std::min(n - 1, std::max(0, static_cast<int>((mu + 1) * 0.5 * n)));
      out[b] += 1;
    }
  });
  const double width = 2.0 / n, rays = static_cast<double>(m.samples);
  std::vector<double> est(n);
  for (int b = 0; b < n; ++b) est[b] = s[b] / (rays * width);
  tables[0].add_batch(est);
  tables[0].attributes["missed_rays"] = std::to_string(static_cast<long long>(s[n]) +
                                                       (tables[0].attributes.count("missed_rays")
                                                            ? std::stoll(tables[0].attributes["missed_rays"])
                                                            : 0));
}

}  // namespace mcref
