#pragma once
// The azimuth of a visible normal given its polar angle, in the unit space
// (vNDF paper Sec. 4.2, Listing 3): the conditional density of phi' given
// theta' (Eq. 22, 26, 27), its tent approximation (Eq. 28–31), and the
// triangle cut (Heitz 2020; models/core/triangle_cut.h) that maps a tent
// sample onto the exact density: no rejection, no iteration. A file of its
// own, with nothing of the micrograin geometry: sim/micrograin/phi_conditional.cpp
// histograms it (the paper's Fig. 5), and only this file of the micrograin
// models enters the simulation fingerprint.
//
// Ranges: cos/sin of theta_i' and theta' in [0, 1]; uniforms in [0, 1).
#include <cmath>

#include "models/core/triangle_cut.h"
#include "models/core/vec.h"

namespace mcref::micrograin {

struct PhiSample {
  double phi, cos_phi, sin_phi;
};

// The conditional density of phi' given theta' over [-phi_q, phi_q], for
// i' at azimuth 0 (Eq. 22, 26, 27 with phi_q), and its tent (Eq. 28–31).
// With a shadow (phi_q < pi) the density vanishes at +-phi_q, so the tent is a
// triangle (h0 = 0) and its inverse depends on u_s alone; the triangle cut is
// taken on the unnormalised density <i'.m'> = a cos phi + b (see
// triangle_cut_scaled), which saves the divisions of the normalisation.
struct PhiConditional {
  PhiConditional(Vec3 i_unit, double cos_theta);
  PhiConditional(double cos_theta_i, double sin_theta_i, double cos_theta, double sin_theta);
  double a, b;    // sin theta_i' sin theta', cos theta_i' cos theta': <i'.m'> = a cos phi + b
  bool shadow;    // part of the ring faces away from i' (Listing 3, line 8)
  double phi_q;   // the bound: pi, or the shadow terminator acos(-b / a)
  double mass;    // 2 (a sin phi_q + b phi_q), the integral of <i'.m'> over [-phi_q, phi_q]
  double pdf(double phi) const { return (a * std::cos(phi) + b) / mass; }            // Eq. 26
  double cdf(double phi) const { return 0.5 + (a * std::sin(phi) + b * phi) / mass; }  // Eq. 22
  double h0() const { return shadow ? 0.0 : (b - a) / mass; }  // pdf(phi_q), the tent's height at its ends
  double tent_pdf(double phi) const;                            // Eq. 28
  double tent_inverse(double u) const;                          // Eq. 31
  // The triangle cut of the tent sample of u_s (Listing 3, lines 16–24).
  TriangleCut cut(double u_s) const;
  // phi' (Listing 3) with its cosine and sine.
  PhiSample sample(double u_s, double u_t) const;

 private:
  // The tent scaled by mass phi_q, at y = |phi| / phi_q: t0 - t1 y.
  double t0() const { return shadow ? mass : kPi * (a + b); }
  double t1() const { return shadow ? mass : 2 * kPi * a; }
  double tent_fraction(double v) const;  // y of the tent sample with |u_s - 1/2| = v
  // f, f', the tent and 2 (u_s - F) at the tent sample x = +-y phi_q, all times
  // mass phi_q (the arguments of triangle_cut_scaled and triangle_cut_point).
  struct CutTerms {
    double f, df, q, d;
  };
  CutTerms cut_terms(double u_s, double x, double y, double sin_x, double cos_x) const;
};

}  // namespace mcref::micrograin
