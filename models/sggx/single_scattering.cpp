// Derivation (one homogeneous slab, depth t in [0, T] from the face the light
// enters; mu = |cos|, Lambda = sigma / mu, tau = T rho).
// A collimated beam of unit irradiance on the entry face has flux density
// (1/mu_i) exp(-rho sigma(i) t / mu_i) at depth t. The power it scatters per
// unit volume and solid angle toward wo is rho sigma(i) F f_p(i->o) times that,
// i.e. fhat_p(i->o) exp(-rho t Lambda_i) / mu_i (Eq. 5). The receiver collects it
// along the ray leaving the exit face along wo: ds = dt / mu_o, attenuated by
// exp(-rho l Lambda_o), l = t (reflection) or T - t (transmission). Hence
//   f_r = fhat_p/(mu_i mu_o) \int_0^T exp(-rho t (L_i + L_o)) dt      (Eq. 8-9)
//       = (fhat_p/rho) G_r / (mu_i mu_o),  G_r = (1 - e^{-tau(L_i+L_o)})/(L_i+L_o)
//   f_t = fhat_p/(mu_i mu_o) \int_0^T exp(-rho t L_i - rho (T-t) L_o) dt   (Eq. 15)
//       = (fhat_p/rho) G_t / (mu_i mu_o),  G_t = (e^{-tau L_o} - e^{-tau L_i})/(L_i - L_o)
// (G_t -> tau e^{-tau L} when L_i = L_o = L). fhat_p/rho = sigma(i) F f_p is
// F D(h)/4 for specular flakes (Eq. 11-12) and albedo * p for HG/isotropic media.
#include "models/sggx/single_scattering.h"

#include <cmath>

namespace mcref::sggx {

double reflection_G(double tau, double lambda_i, double lambda_o) {
  const double s = lambda_i + lambda_o;
  if (!(tau > 0)) return 0;
  return -std::expm1(-tau * s) / s;  // tau = inf: 1/s
}

double transmission_G(double tau, double lambda_i, double lambda_o) {
  if (!(tau > 0) || std::isinf(tau)) return 0;
  const double lo = std::fmin(lambda_i, lambda_o), x = tau * std::fabs(lambda_i - lambda_o);
  const double phi = x > 0 ? -std::expm1(-x) / x : 1.0;  // (1 - e^-x)/x, phi(0) = 1
  return tau * std::exp(-tau * lo) * phi;
}

double transmission_G_eq16_as_printed(double tau, double lambda_i, double lambda_o_signed) {
  const double s = lambda_i + lambda_o_signed;
  return (1 - std::exp(-tau * s)) / s * std::exp(tau * lambda_o_signed);
}

std::vector<double> single_scattering_lobes(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo) {
  const std::size_t n = stack.size();
  std::vector<double> lobes(n, 0.0);
  const double mi = std::fabs(wi.z), mo = std::fabs(wo.z);
  if (!(mi > 0) || !(mo > 0)) return lobes;
  const bool from_top = wi.z > 0, reflection = (wi.z > 0) == (wo.z > 0);
  // Visit layers in the order the incident light crosses them.
  std::vector<double> depth_i(n), depth_o(n);  // tau_j Lambda_j(w) of each layer
  for (std::size_t j = 0; j < n; ++j) {
    const double tau = stack[j].optical_thickness();
    depth_i[j] = tau > 0 ? tau * stack[j].sigma(wi) / mi : 0.0;
    depth_o[j] = tau > 0 ? tau * stack[j].sigma(wo) / mo : 0.0;
  }
  std::vector<std::size_t> order(n);
  for (std::size_t step = 0; step < n; ++step) order[step] = from_top ? step : n - 1 - step;
  // after_o[step]: optical depth along wo of the layers crossed after order[step]
  // (suffix sums, no subtraction, so infinite layers stay well defined).
  std::vector<double> after_o(n + 1, 0.0);
  for (std::size_t step = n; step-- > 0;) after_o[step] = after_o[step + 1] + depth_o[order[step]];
  double before_i = 0, before_o = 0;  // layers crossed before reaching layer k
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t k = order[step];
    const Layer& layer = stack[k];
    const double tau = layer.optical_thickness();
    const double li = layer.sigma(wi) / mi, lo = layer.sigma(wo) / mo;
    const double g = reflection ? reflection_G(tau, li, lo) : transmission_G(tau, li, lo);
    const double attenuation =
        std::exp(-(before_i + (reflection ? before_o : after_o[step + 1])));
    if (g > 0 && attenuation > 0) lobes[k] = attenuation * layer.reduced_phase(wi, wo) * g / (mi * mo);
    before_i += depth_i[k];
    before_o += depth_o[k];
  }
  return lobes;
}

namespace {
double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}
}  // namespace

double single_scattering_reflection(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo) {
  if ((wi.z > 0) != (wo.z > 0)) return 0;
  return sum(single_scattering_lobes(stack, wi, wo));
}

double single_scattering_transmission(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo) {
  if ((wi.z > 0) == (wo.z > 0)) return 0;
  return sum(single_scattering_lobes(stack, wi, wo));
}

double single_scattering_bsdf(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo) {
  return sum(single_scattering_lobes(stack, wi, wo));
}

double delta_transmittance(const std::vector<Layer>& stack, Vec3 w) {
  const double mu = std::fabs(w.z);
  if (!(mu > 0)) return 0;
  double depth = 0;
  for (const Layer& l : stack) {
    const double tau = l.optical_thickness();
    if (tau > 0) depth += tau * l.sigma(w) / mu;
  }
  return std::exp(-depth);
}

double substrate_term(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo, double substrate_bsdf) {
  if (!(wi.z > 0) || !(wo.z > 0)) return 0;
  return substrate_bsdf * delta_transmittance(stack, wi) * delta_transmittance(stack, wo);
}

double lambertian_substrate_term(const std::vector<Layer>& stack, Vec3 wi, Vec3 wo, double albedo) {
  return substrate_term(stack, wi, wo, albedo / kPi);
}

}  // namespace mcref::sggx
