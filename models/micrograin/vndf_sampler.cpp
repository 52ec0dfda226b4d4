#include "models/micrograin/vndf_sampler.h"

#include <algorithm>
#include <cmath>

#include "models/micrograin/projected_area.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {

constexpr int kN = VndfSampler::kResolution;
constexpr int kFine = 4096;  // sigma evaluations per table row

// Rows: cos theta_i at (j + 0.5) / kN; shadow range of h: [0, sin theta_i].
double row_cos(int j) { return (j + 0.5) / kN; }

double shadow_floor(double cos_i) { return kPi * cos_i * cos_i; }            // sigma(n, sin theta_i)
double sigma_at_zero(double cos_i) { return 0.5 * kPi * (1 + 1 / cos_i); }  // sigma(i, 0)

}  // namespace

VndfSampler::VndfSampler() : table_(static_cast<std::size_t>(kN) * kN) {
  std::vector<double> h(kFine + 1), s(kFine + 1);
  for (int j = 0; j < kN; ++j) {
    const double ci = row_cos(j), si = std::sqrt(1 - ci * ci);
    const Vec3 i{si, 0, ci};
    const double lo = shadow_floor(ci), hi = sigma_at_zero(ci);
    // sigma decreases in h: tabulate on a fine grid of h, then invert by a monotone scan.
    for (int k = 0; k <= kFine; ++k) {
      h[k] = si * k / kFine;
      s[k] = k == 0 ? hi : (k == kFine ? lo : projected_cap_area(i, h[k]));
      if (k > 0) s[k] = std::min(s[k], s[k - 1]);
    }
    int k = kFine;
    for (int c = 0; c < kN; ++c) {
      const double target = lo + (hi - lo) * c / (kN - 1);  // columns include both ends
      while (k > 0 && s[k - 1] <= target) --k;               // s[k-1] > target >= s[k]
      double v;
      if (k == 0) v = 0;
      else {
        const double t = (s[k - 1] - target) / std::max(1e-300, s[k - 1] - s[k]);
        v = h[k - 1] + t * (h[k] - h[k - 1]);
      }
      table_[static_cast<std::size_t>(j) * kN + c] = static_cast<float>(v);
    }
  }
}

double VndfSampler::inverse_sigma(double ci, double xi_area) const {
  const double lo = shadow_floor(ci), hi = sigma_at_zero(ci);
  const double x = std::clamp((xi_area - lo) / (hi - lo), 0.0, 1.0) * (kN - 1);
  const double y = std::clamp(ci * kN - 0.5, 0.0, kN - 1.0);
  const int c0 = std::min(static_cast<int>(x), kN - 2), r0 = std::min(static_cast<int>(y), kN - 2);
  const double fx = x - c0, fy = y - r0;
  const float* a = &table_[static_cast<std::size_t>(r0) * kN + c0];
  const float* b = a + kN;
  // Rows hold h / sin theta_i of their own row implicitly (h ranges differ):
  // interpolate the normalised value h / sin theta_row, then rescale.
  const double s0 = std::sqrt(1 - row_cos(r0) * row_cos(r0)), s1 = std::sqrt(1 - row_cos(r0 + 1) * row_cos(r0 + 1));
  const double top = (1 - fx) * a[0] / s0 + fx * a[1] / s0, bottom = (1 - fx) * b[0] / s1 + fx * b[1] / s1;
  return ((1 - fy) * top + fy * bottom) * std::sqrt(std::max(0.0, 1 - ci * ci));
}

double VndfSampler::sample_cos_theta(double tau0, Vec3 iu, double xi) const {
  const double rho = -std::log1p(-tau0) / kPi;  // unit-space density
  const double ci = iu.z;
  const double tau_i0 = -std::expm1(-rho * sigma_at_zero(ci));
  const double area = -std::log1p(-xi * tau_i0) / rho;  // Eq. 23: sigma(i', cos theta) = Xi
  if (area <= shadow_floor(ci)) return std::sqrt(std::max(0.0, 1 - area / kPi));  // Eq. 25
  return inverse_sigma(ci, area);
}

double tent_inverse(double phi_q, double h0, double xi) {
  const double h1 = 1 / phi_q - h0, slope = (h0 - h1) / phi_q;  // P~(phi) = h1 + slope |phi|
  // CDF for phi >= 0: 1/2 + h1 phi + slope phi^2 / 2; symmetric below.
  const double u = std::fabs(xi - 0.5);
  double p;
  if (std::fabs(slope) < 1e-12) p = u / h1;
  else p = (-h1 + std::sqrt(std::max(0.0, h1 * h1 + 2 * slope * u))) / slope;
  p = std::min(p, phi_q);
  return xi < 0.5 ? -p : p;
}

double VndfSampler::sample_phi(Vec3 iu, double ct, double xi) {
  const double ci = iu.z, si = std::sqrt(std::max(0.0, 1 - ci * ci));
  const double st = std::sqrt(std::max(0.0, 1 - ct * ct));
  double phq = kPi;
  if (si > ct) phq = std::acos(std::clamp(-(ct * ci) / (st * si), -1.0, 1.0));  // Listing 3 line 8
  const double a = si * st, b = ci * ct;
  const double norm = 1 / (2 * (std::sin(phq) * a + phq * b));                 // Eq. 22 denominator
  auto cdf = [&](double p) { return 0.5 + norm * (std::sin(p) * a + p * b); }; // Eq. 22
  auto pdf = [&](double p) { return norm * (std::cos(p) * a + b); };           // Eq. 26
  const double h0 = pdf(phq);
  double p = tent_inverse(phq, std::max(0.0, h0), xi), lo = -phq, hi = phq;
  for (int it = 0; it < 40; ++it) {
    const double e = cdf(p) - xi;
    if (std::fabs(e) < 1e-12) return p;
    if (e > 0) hi = p; else lo = p;
    const double d = pdf(p);
    double next = d > 0 ? p - e / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - p) < 1e-13) return next;
    p = next;
  }
  return p;
}

Vec3 VndfSampler::sample_unit(double tau0, Vec3 iu, double u1, double u2) const {
  const double ct = sample_cos_theta(tau0, iu, u1), st = std::sqrt(std::max(0.0, 1 - ct * ct));
  const double phi = sample_phi(iu, ct, u2);
  const Vec3 m{std::cos(phi) * st, std::sin(phi) * st, ct};
  const double r = std::hypot(iu.x, iu.y);
  if (r <= 0) return m;
  const double rx = iu.x / r, ry = iu.y / r;  // Listing 4: rotate to the azimuth of i'
  return {m.x * rx - m.y * ry, m.x * ry + m.y * rx, m.z};
}

Vec3 VndfSampler::sample(const GrainField& f, Vec3 i, double u1, double u2) const {
  return from_unit_normal(f, sample_unit(f.tau0, to_unit_direction(f, i), u1, u2));
}

}  // namespace mcref::micrograin
