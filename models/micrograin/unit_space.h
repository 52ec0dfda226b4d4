#pragma once
// The "unit space" of a micrograin field (vNDF paper Sec. 3, Fig. 3, Eq. 7–12):
// x/r_x, y/r_y, z/c, in which every grain is a unit hemisphere. With
// M^-1 = diag(beta_x, beta_y, 1) (up to the common factor c):
//   direction  d  ->  d' = M^-1 d / |M^-1 d|     ∝ (beta_x d.x, beta_y d.y, d.z)
//   normal     m  ->  m' = M^T  m / |M^T  m|     ∝ (m.x / beta_x, m.y / beta_y, m.z)
// (normals transform with the inverse transpose). Masking is invariant under
// this linear map, and for a unit hemisphere the height of the surface point
// of unit-space normal m' is h = m'.z.
//
// Inputs: unit vectors (any hemisphere; the maps keep the sign of z and the
// azimuth quadrant); fields with beta_x, beta_y > 0.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Real direction -> unit-space direction (unit length).
Vec3 to_unit_direction(const GrainField& f, Vec3 d);
// Unit-space direction -> real direction (unit length).
Vec3 from_unit_direction(const GrainField& f, Vec3 d_unit);

// Real normal -> unit-space normal (unit length).
Vec3 to_unit_normal(const GrainField& f, Vec3 m);
// Unit-space normal -> real normal (unit length).
Vec3 from_unit_normal(const GrainField& f, Vec3 m_unit);

// |M^T m| = sqrt(m.x^2/beta_x^2 + m.y^2/beta_y^2 + m.z^2) for a unit real normal m.
double normal_stretch(const GrainField& f, Vec3 m);

// Jacobian of the normal map, d omega' / d omega = det(M) / |M^T m|^3
// with det(M) = 1 / (beta_x beta_y) (vNDF paper Eq. 7/11).
double unit_normal_jacobian(const GrainField& f, Vec3 m);

// Unit-space height of the grain point of real normal m: h = m'.z (vNDF Sec. 2).
double unit_height(const GrainField& f, Vec3 m);

}  // namespace mcref::micrograin
