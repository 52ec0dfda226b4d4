#include "sim/estimators/estimator.h"

#include <tbb/parallel_for.h>

#include <map>
#include <stdexcept>

namespace mcref {

Sums run_chunks(std::uint64_t samples, std::size_t sums_size, std::uint64_t key,
                const std::function<void(Rng&, std::uint64_t, Sums&)>& body) {
  const std::uint64_t chunks = (samples + kChunkSamples - 1) / kChunkSamples;
  std::vector<Sums> partial(chunks);
  tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
    partial[c].assign(sums_size, 0.0);  // allocated and zeroed by the worker: in its cache
    Rng rng(stream_seed({key, c}));
    const std::uint64_t begin = c * kChunkSamples;
    const std::uint64_t count = std::min(kChunkSamples, samples - begin);
    body(rng, count, partial[c]);
  });
  Sums total(sums_size, 0.0);
  for (const Sums& p : partial)
    for (std::size_t i = 0; i < sums_size; ++i) total[i] += p[i];
  return total;
}

Axis theta_points(const std::string& name, const std::vector<double>& v) { return Axis::points(name, "rad", v); }
Axis phi_points(const std::string& name, const std::vector<double>& v) { return Axis::points(name, "rad", v); }
Axis theta_bins(const std::string& name, int n) { return Axis::uniform_bins(name, "rad", 0.0, kPi / 2, n); }
Axis phi_bins(const std::string& name, int n, bool folded) {
  return Axis::uniform_bins(name, "rad", 0.0, folded ? kPi : 2 * kPi, n);
}

double cell_solid_angle(double t0, double t1, double p0, double p1) {
  return (std::cos(t0) - std::cos(t1)) * (p1 - p0);
}
double cell_projected_solid_angle(double t0, double t1, double p0, double p1) {
  const double s0 = std::sin(t0), s1 = std::sin(t1);
  return 0.5 * (s1 * s1 - s0 * s0) * (p1 - p0);
}


// The registry; each estimator lives in its own file.
Estimator p1_estimator();
Estimator ndf_estimator();
Estimator tau_plus_estimator();
Estimator tau_height_estimator();
Estimator g1_estimator();
Estimator pore_visibility_estimator();
Estimator vndf_estimator();
Estimator micrograin_brdf_estimator();

const Estimator& estimator_for(const std::string& quantity) {
  static const std::map<std::string, Estimator> registry{
      {"p1", p1_estimator()},
      {"ndf", ndf_estimator()},
      {"tau_plus", tau_plus_estimator()},
      {"tau_height", tau_height_estimator()},
      {"g1", g1_estimator()},
      {"pore_visibility", pore_visibility_estimator()},
      {"vndf", vndf_estimator()},
      {"brdf", micrograin_brdf_estimator()},
  };
  const auto it = registry.find(quantity);
  if (it == registry.end()) throw std::invalid_argument("no estimator for quantity " + quantity);
  return it->second;
}

}  // namespace mcref
