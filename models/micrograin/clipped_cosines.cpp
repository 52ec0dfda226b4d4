#include "models/micrograin/clipped_cosines.h"

#include <algorithm>
#include <cmath>

#include "models/core/vec.h"

namespace mcref::micrograin {

void add_sinusoid_zeros(const Sinusoid& p, std::vector<double>& cuts) {
  const double R = std::hypot(p.B, p.C);
  if (R <= std::fabs(p.A)) return;  // the whole ring on one side
  const double a0 = std::atan2(p.C, p.B), w = std::acos(-p.A / R);
  for (double z : {a0 - w, a0 + w}) cuts.push_back(std::fmod(std::fmod(z, 2 * kPi) + 2 * kPi, 2 * kPi));
}

double clipped_product_integral(const Sinusoid& p, const Sinusoid& q) {
  std::vector<double> cuts{0.0, 2 * kPi};
  add_sinusoid_zeros(p, cuts);
  add_sinusoid_zeros(q, cuts);
  std::sort(cuts.begin(), cuts.end());
  // p q = k0 + k1 cos a + k2 sin a + k3 cos 2a + k4 sin 2a.
  const double k0 = p.A * q.A + 0.5 * (p.B * q.B + p.C * q.C);
  const double k1 = p.A * q.B + q.A * p.B, k2 = p.A * q.C + q.A * p.C;
  const double k3 = 0.5 * (p.B * q.B - p.C * q.C), k4 = 0.5 * (p.B * q.C + p.C * q.B);
  double sum = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double a = cuts[k], b = cuts[k + 1], m = 0.5 * (a + b), d = 0.5 * (b - a);
    if (!(d > 0)) continue;
    const double cm = std::cos(m), sm = std::sin(m);
    if (p.A + p.B * cm + p.C * sm <= 0 || q.A + q.B * cm + q.C * sm <= 0) continue;  // one is clipped on the piece
    // ∫_a^b of each term: cos -> 2 cos m sin d, sin -> 2 sin m sin d,
    // cos 2a -> cos 2m sin 2d, sin 2a -> sin 2m sin 2d.
    const double sd = std::sin(d), s2d = std::sin(2 * d), c2m = cm * cm - sm * sm, s2m = 2 * sm * cm;
    sum += k0 * 2 * d + 2 * sd * (k1 * cm + k2 * sm) + s2d * (k3 * c2m + k4 * s2m);
  }
  return sum;
}

}  // namespace mcref::micrograin
