#pragma once
// Shared case list for the SGGX chi-square tests: surface- and fibre-like S,
// alpha in {0.1, 0.5, 1}, axis-aligned and tilted orientation w_p, three
// incident directions (near normal, oblique, from below).
#include <string>
#include <vector>

#include "models/core/vec.h"
#include "models/sggx/sggx_distribution.h"

namespace mcref::sggx_test {

struct SggxChi2Case {
  bool fiber;
  double alpha;
  bool tilted;
  double theta_i, phi_i;
  Vec3 wp() const { return tilted ? spherical_direction(0.7, 0.5) : Vec3{0, 0, 1}; }
  Vec3 wi() const { return spherical_direction(theta_i, phi_i); }
  sggx::Sggx sggx() const { return fiber ? sggx::fiber_like(alpha, wp()) : sggx::surface_like(alpha, wp()); }
};

inline std::vector<SggxChi2Case> sggx_chi2_cases() {
  std::vector<SggxChi2Case> c;
  for (bool fiber : {false, true})
    for (double a : {0.1, 0.5, 1.0})
      for (bool tilted : {false, true})
        for (auto ang : {std::pair<double, double>{0.2, 0.3}, {1.3, 2.0}, {2.5, 4.0}})
          c.push_back({fiber, a, tilted, ang.first, ang.second});
  return c;
}

inline std::string sggx_chi2_case_name(const SggxChi2Case& c, std::size_t index) {
  return std::string(c.fiber ? "fiber" : "surface") + "_a" + std::to_string(static_cast<int>(c.alpha * 100 + 0.5)) +
         (c.tilted ? "_tilted" : "_z") + "_thetai" + std::to_string(static_cast<int>(c.theta_i * 10 + 0.5)) +
         "_" + std::to_string(index);
}

}  // namespace mcref::sggx_test
