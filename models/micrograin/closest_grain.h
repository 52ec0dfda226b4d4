#pragma once
// First-order statistic of the distance from a point of the plane to the
// closest grain centre of a Poisson process of density rho (LRPB23 Sec. 4.1).
//
// Ranges: rho >= 0 (centres per unit area), r >= 0, n >= 1.

namespace mcref::micrograin {

// Eq. 8: p1(r) = 2 pi rho r exp(-pi rho r^2).
double closest_grain_distance_pdf(double r, double rho);

// Eq. 9: P1(r) = 1 - exp(-pi rho r^2). At r = r_s this is tau0 (Eq. 13).
double closest_grain_distance_cdf(double r, double rho);

// Eq. 10: density of the closest centre per unit AREA at polar coordinates
// (r, phi) around the point: rho exp(-pi rho r^2). (The paper writes it as
// p1(r) p(phi); that product is the density per unit r per unit phi and
// carries an extra factor r: p1(r)/(2 pi) = r * rho exp(-pi rho r^2).)
double closest_grain_polar_pdf(double r, double rho);

// Eq. 7: the finite-n statistic p1_n(r) = 2 pi rho r (1 - pi rho r^2 / n)^(n-1)
// for n centres uniform in a disc of radius R = sqrt(n / (pi rho)); zero for
// r > R. Tends to Eq. 8 as n -> infinity.
double closest_grain_distance_pdf_finite(double r, double rho, double n);

}  // namespace mcref::micrograin
