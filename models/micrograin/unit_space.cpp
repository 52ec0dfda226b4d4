#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

Vec3 to_unit_direction(const GrainField& f, Vec3 d) {
  return normalize(Vec3{d.x * f.beta_x, d.y * f.beta_y, d.z});
}

Vec3 from_unit_direction(const GrainField& f, Vec3 d_unit) {
  return normalize(Vec3{d_unit.x / f.beta_x, d_unit.y / f.beta_y, d_unit.z});
}

Vec3 to_unit_normal(const GrainField& f, Vec3 m) {
  return normalize(Vec3{m.x / f.beta_x, m.y / f.beta_y, m.z});
}

Vec3 from_unit_normal(const GrainField& f, Vec3 m_unit) {
  return normalize(Vec3{m_unit.x * f.beta_x, m_unit.y * f.beta_y, m_unit.z});
}

double normal_stretch(const GrainField& f, Vec3 m) {
  const double ax = m.x / f.beta_x, ay = m.y / f.beta_y;
  return std::sqrt(ax * ax + ay * ay + m.z * m.z);
}

double unit_normal_jacobian(const GrainField& f, Vec3 m) {
  const double s = normal_stretch(f, m);
  return 1.0 / (f.beta_x * f.beta_y * s * s * s);
}

double unit_height(const GrainField& f, Vec3 m) { return m.z / normal_stretch(f, m); }

}  // namespace mcref::micrograin
