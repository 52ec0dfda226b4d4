#include "sim/micrograin/estimator.h"

#include <cmath>
#include <map>
#include <stdexcept>

namespace mcref {

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
Estimator phi_conditional_estimator();
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
      {"phi_conditional", phi_conditional_estimator()},
      {"brdf", micrograin_brdf_estimator()},
  };
  const auto it = registry.find(quantity);
  if (it == registry.end()) throw std::invalid_argument("no estimator for quantity " + quantity);
  return it->second;
}

}  // namespace mcref
