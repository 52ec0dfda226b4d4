#pragma once
// Visible filling factor of a micrograin layer and the layer weight w+
// (LRPB23 Sec. 5.1, Eq. 21–24).
//
// Isotropic forms take (tau0, beta, theta); the direction forms take a real
// direction and a GrainField and work in the unit space, where beta = 1 and
// theta is replaced by the unit-space angle theta' of the mapped direction
// (gamma_beta(theta)/cos theta = 1/cos theta', so both agree when beta_x == beta_y).
//
// Ranges: tau0 in (0, 1); beta > 0; theta in [0, pi/2) (the limit pi/2 gives 1);
// directions unit length with d.z > 0.
#include "models/core/vec.h"
#include "models/micrograin/grain_field.h"

namespace mcref::micrograin {

// Eq. 21 (text below it): compression factor gamma_beta(theta) = sqrt(cos^2 + beta^2 sin^2).
double compression_factor(double beta, double theta);

// Eq. 21: visible filling factor of full ellipsoids, tau_beta = 1 - (1-tau0)^(gamma_beta/cos theta).
double tau_beta(double tau0, double beta, double theta);
double tau_beta(const GrainField& f, Vec3 d);

// Eq. 22: visible filling factor of the upper half-ellipsoids,
// tau+ = 1 - sqrt((1 - tau_beta)(1 - tau0)).
double tau_plus(double tau0, double beta, double theta);
double tau_plus(const GrainField& f, Vec3 d);

// Eq. 24: layer weight w+(i, o) = 1 - sqrt((1 - tau_beta(i))(1 - tau_beta(o))).
double layer_weight(const GrainField& f, Vec3 i, Vec3 o);

// Eq. 23 from given visible filling factors (e.g. measured ones):
// w+ = 1 - (1 - tau+_i)(1 - tau+_o) / (1 - tau0). Equals Eq. 24 when tau+ is Eq. 22.
double layer_weight_eq23(double tau0, double tau_plus_i, double tau_plus_o);

}  // namespace mcref::micrograin
