#include "models/micrograin/vndf_sampler.h"

#include <algorithm>
#include <cmath>

#include "models/core/small_angle.h"
#include "models/micrograin/projected_area.h"
#include "models/micrograin/unit_space.h"

namespace mcref::micrograin {

namespace {

constexpr int kN = VndfSampler::kResolution;
constexpr int kFine = 4096;  // sigma evaluations per table row
// 16-bit fixed point: a step of 1.5e-5, far below the bilinear error of the
// 1024 x 1024 table (~2e-3 in h); 2 MiB, so it stays in a core's L2 cache.
constexpr double kTableScale = 65535;

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
      const double unit = std::clamp(v / si, 0.0, 1.0);  // h / sin theta_i of the row
      table_[static_cast<std::size_t>(j) * kN + c] = static_cast<std::uint16_t>(std::lround(unit * kTableScale));
    }
  }
}

double VndfSampler::inverse_sigma(double ci, double xi_area) const {
  return inverse_sigma(ci, std::sqrt(std::max(0.0, 1 - ci * ci)), xi_area);
}

double VndfSampler::inverse_sigma(double ci, double si, double xi_area) const {
  const double lo = shadow_floor(ci), hi = sigma_at_zero(ci);
  const double x = std::clamp((xi_area - lo) / (hi - lo), 0.0, 1.0) * (kN - 1);
  const double y = std::clamp(ci * kN - 0.5, 0.0, kN - 1.0);
  const int c0 = std::min(static_cast<int>(x), kN - 2), r0 = std::min(static_cast<int>(y), kN - 2);
  const double fx = x - c0, fy = y - r0;
  const std::uint16_t* a = &table_[static_cast<std::size_t>(r0) * kN + c0];
  const std::uint16_t* b = a + kN;
  // Rows hold h / sin theta_i (the range of h, [0, sin theta_i], differs per row).
  const double top = a[0] + fx * (a[1] - a[0]), bottom = b[0] + fx * (b[1] - b[0]);
  return (top + fy * (bottom - top)) * (si / kTableScale);
}

SinCos VndfSampler::sample_theta(double tau0, double ci, double si, double xi) const {
  // 1 - tau(i', 0) = exp(-rho' sigma(i', 0)) = (1 - tau0)^(sigma(i', 0) / pi), rho' = -ln(1 - tau0) / pi.
  // exp and log rather than expm1 and log1p (two thirds of their latency here):
  // the arguments' rounding moves Xi by at most ~4e-16 / tau0 in absolute
  // terms, far below any bin.
  const double log_gap = std::log(1 - tau0);
  const double gap_i0 = std::exp(log_gap * sigma_at_zero(ci) / kPi);
  const double xi_area = std::log(1 - xi * (1 - gap_i0)) * (kPi / log_gap);  // Eq. 23: sigma(i', cos theta) = Xi
  if (xi_area <= shadow_floor(ci)) {  // Eq. 25: cos^2 theta = 1 - Xi / pi, sin^2 theta = Xi / pi
    const double s2 = std::max(0.0, xi_area / kPi);
    return {std::sqrt(s2), std::sqrt(std::max(0.0, 1 - s2))};
  }
  const double ct = inverse_sigma(ci, si, xi_area);
  return {std::sqrt(std::max(0.0, 1 - ct * ct)), ct};
}

double VndfSampler::sample_cos_theta(double tau0, double ci, double si, double xi) const {
  return sample_theta(tau0, ci, si, xi).cos;
}

double VndfSampler::sample_phi(Vec3 iu, double ct, double u_s, double u_t) {
  return PhiConditional(iu, ct).sample(u_s, u_t).phi;
}

Vec3 VndfSampler::sample_unit(double tau0, Vec3 iu, double u1, double u2, double u3) const {
  const double ci = iu.z, si = std::sqrt(std::max(0.0, 1 - ci * ci));
  const SinCos t = sample_theta(tau0, ci, si, u1);
  const PhiSample p = PhiConditional(ci, si, t.cos, t.sin).sample(u2, u3);
  const Vec3 m{p.cos_phi * t.sin, p.sin_phi * t.sin, t.cos};
  if (!(si > 0)) return m;
  const double inv_si = 1 / si, rx = iu.x * inv_si, ry = iu.y * inv_si;  // Listing 4: rotate to the azimuth of i'
  return {m.x * rx - m.y * ry, m.x * ry + m.y * rx, m.z};
}

Vec3 VndfSampler::sample(const GrainField& f, Vec3 i, double u1, double u2, double u3) const {
  return from_unit_normal(f, sample_unit(f.tau0, to_unit_direction(f, i), u1, u2, u3));
}

}  // namespace mcref::micrograin
