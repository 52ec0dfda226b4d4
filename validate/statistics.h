#pragma once
// Distribution functions for the verdicts: normal, Student t, chi-squared.
namespace mcref {

double normal_cdf(double z);
// Inverse of normal_cdf, p in (0, 1).
double normal_quantile(double p);
// Regularised incomplete beta I_x(a, b).
double regularized_beta(double x, double a, double b);
// Regularised upper incomplete gamma Q(a, x).
double regularized_gamma_q(double a, double x);
// CDF of Student's t with nu degrees of freedom.
double student_t_cdf(double t, double nu);
// P(X >= x) for X ~ chi-squared with k degrees of freedom.
double chi2_survival(double x, double k);
// The |z| bound that n independent normal cells all stay below with
// probability 1 - alpha (Sidak): Phi^-1(1 - (1 - (1 - alpha)^(1/n)) / 2).
double sidak_z_bound(double alpha, double n);

}  // namespace mcref
