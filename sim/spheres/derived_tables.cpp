#include "sim/spheres/derived_tables.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "models/core/quadrature.h"
#include "models/core/vec.h"

namespace mcref {

namespace {
std::size_t find_axis(const Table& t, const std::string& name) {
  for (std::size_t i = 0; i < t.axes.size(); ++i)
    if (t.axes[i].name == name) return i;
  throw std::invalid_argument("table " + t.name + " has no axis " + name);
}
}  // namespace

std::vector<double> fourier_mode_weights(const Axis& phi, int k) {
  const std::size_t n = phi.size();
  if (phi.kind != Axis::Kind::Bins || n == 0 || std::fabs(phi.lower(0)) > 1e-12 ||
      std::fabs(phi.upper(n - 1) - kPi) > 1e-9)
    throw std::invalid_argument("Fourier modes need phi bins covering [0, pi] (folded azimuth)");
  const double width = kPi / static_cast<double>(n);
  for (std::size_t b = 0; b < n; ++b)
    if (std::fabs(phi.upper(b) - phi.lower(b) - width) > 1e-9)
      throw std::invalid_argument("Fourier modes need uniform phi bins");
  const double x = 0.5 * k * width;
  const double sinc = k == 0 ? 1.0 : std::sin(x) / x;
  std::vector<double> w(n);
  for (std::size_t b = 0; b < n; ++b) {
    // \int_b cos(k phi) dphi, exactly.
    const double a = phi.lower(b), c = phi.upper(b);
    const double integral = k == 0 ? c - a : (std::sin(k * c) - std::sin(k * a)) / k;
    w[b] = (k == 0 ? 1.0 : 2.0) / kPi * integral / (sinc * sinc);
  }
  return w;
}

Table make_mode_table(const Table& brdf, int max_mode) {
  std::vector<double> ks;
  for (int k = 0; k <= max_mode; ++k) ks.push_back(k);
  Table t(brdf.name + "_modes", "brdf_modes",
          {brdf.axes[find_axis(brdf, "theta_i")], brdf.axes[find_axis(brdf, "theta_o")],
           Axis::points("k", "1", ks), brdf.axes[find_axis(brdf, "channel")]});
  t.units = "1/sr";
  t.description =
      "azimuthal Fourier modes f^(k) of the total BRDF (Eq. 9: f = f0 + f1 cos phi + f2 cos 2phi), per batch from "
      "the folded phi bins (sinc-corrected, exact below mode 2 N - 3), cosine-weighted theta_o bin averages, "
      "averaged over phi_i";
  t.attributes = brdf.attributes;
  t.attributes["component"] = "total";
  return t;
}

std::vector<double> mode_estimate(const Table& brdf, const std::vector<double>& f, const Table& modes) {
  const std::size_t ai = find_axis(brdf, "theta_i"), api = find_axis(brdf, "phi_i"), ao = find_axis(brdf, "theta_o"),
                    ap = find_axis(brdf, "phi"), ac = find_axis(brdf, "channel");
  if (ai != 0 || api != 1 || ao != 2 || ap != 3 || ac != 4 || brdf.axes.size() != 5)
    throw std::invalid_argument("mode_estimate: brdf axes must be theta_i, phi_i, theta_o, phi, channel");
  const std::size_t NI = brdf.axes[0].size(), NPI = brdf.axes[1].size(), NO = brdf.axes[2].size(),
                    NP = brdf.axes[3].size(), NC = brdf.axes[4].size();
  const std::size_t NK = modes.axes[2].size();
  std::vector<std::vector<double>> w(NK);
  for (std::size_t k = 0; k < NK; ++k) w[k] = fourier_mode_weights(brdf.axes[3], static_cast<int>(modes.axes[2].values[k]));
  std::vector<double> out(modes.cells(), 0.0);
  for (std::size_t i = 0; i < NI; ++i)
    for (std::size_t pi = 0; pi < NPI; ++pi)
      for (std::size_t o = 0; o < NO; ++o)
        for (std::size_t k = 0; k < NK; ++k)
          for (std::size_t c = 0; c < NC; ++c) {
            double s = 0;
            for (std::size_t p = 0; p < NP; ++p) s += w[k][p] * f[(((i * NPI + pi) * NO + o) * NP + p) * NC + c];
            out[((i * NO + o) * NK + k) * NC + c] += s / static_cast<double>(NPI);
          }
  return out;
}

std::vector<double> spherical_albedo_weights(const std::vector<double>& theta_i) {
  const int n = static_cast<int>(theta_i.size());
  if (n < 2) return {};
  const GaussLegendre gl(n);
  std::vector<double> mu(n);
  for (int j = 0; j < n; ++j) mu[j] = std::cos(theta_i[j]);
  std::vector<double> w(n);
  std::vector<bool> used(n, false);
  for (int j = 0; j < n; ++j) {
    bool found = false;
    for (int q = 0; q < n; ++q) {
      const double node = 0.5 * (1 + gl.x[q]);
      if (!used[q] && std::fabs(node - mu[j]) < 1e-9) {
        used[q] = true;
        w[j] = 0.5 * gl.w[q];
        found = true;
        break;
      }
    }
    if (!found) return {};
  }
  return w;
}

Table make_kd_table(const Table& albedo) {
  Table t(albedo.name.substr(0, albedo.name.size() - std::string("_albedo").size()) + "_kd", "spherical_albedo",
          {albedo.axes[find_axis(albedo, "channel")]});
  t.units = "1";
  t.description =
      "spherical (bond) albedo k_d = 2 \\int_0^1 a(mu) mu dmu of the total directional albedo a (delta lobes "
      "included), Gauss-Legendre over the measure's theta_i, averaged over phi_i, per batch";
  t.attributes = albedo.attributes;
  return t;
}

std::vector<double> kd_estimate(const Table& albedo, const std::vector<double>& a, const std::vector<double>& weights) {
  const std::size_t ai = find_axis(albedo, "theta_i"), api = find_axis(albedo, "phi_i"),
                    acomp = find_axis(albedo, "component"), ac = find_axis(albedo, "channel");
  if (ai != 0 || api != 1 || acomp != 2 || ac != 3)
    throw std::invalid_argument("kd_estimate: albedo axes must be theta_i, phi_i, component, channel");
  const std::size_t NI = albedo.axes[0].size(), NPI = albedo.axes[1].size(), NCOMP = albedo.axes[2].size(),
                    NC = albedo.axes[3].size();
  if (weights.size() != NI) throw std::invalid_argument("kd_estimate: one weight per theta_i");
  std::vector<double> out(NC, 0.0);
  for (std::size_t i = 0; i < NI; ++i) {
    const double mu = std::cos(albedo.axes[0].values[i]);
    for (std::size_t pi = 0; pi < NPI; ++pi)
      for (std::size_t c = 0; c < NC; ++c)
        out[c] += 2 * weights[i] * mu * a[((i * NPI + pi) * NCOMP + (NCOMP - 1)) * NC + c] / static_cast<double>(NPI);
  }
  return out;
}

}  // namespace mcref
