#include "sim/tally/brdf_interpolation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "models/core/vec.h"
#include "sim/experiment/config_error.h"

namespace mcref {

namespace {

std::string deg(double rad) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", rad * 180 / kPi);
  return b;
}

// Lower index and weight of x among increasing points p (held constant outside).
void locate(const std::vector<double>& p, double x, std::size_t& i, double& w) {
  if (p.size() == 1 || x <= p.front()) { i = 0; w = 0; return; }
  if (x >= p.back()) { i = p.size() - 2; w = 1; return; }
  i = static_cast<std::size_t>(std::upper_bound(p.begin(), p.end(), x) - p.begin()) - 1;
  w = (x - p[i]) / (p[i + 1] - p[i]);
}

// An axis's positions: points, or bin centres; refused unless in radians and increasing.
template <class Refuse>
std::vector<double> positions(const Axis& a, const Refuse& refuse) {
  if (a.unit != "rad") refuse("axis '" + a.name + "' is in \"" + a.unit + "\"; export needs angles in rad");
  std::vector<double> p;
  for (std::size_t k = 0; k < a.size(); ++k) p.push_back(a.centre(k));
  for (std::size_t k = 1; k < p.size(); ++k)
    if (!(p[k] > p[k - 1])) refuse("axis '" + a.name + "' is not increasing (" + deg(p[k - 1]) + " then " + deg(p[k]) + " deg)");
  return p;
}

}  // namespace

BrdfInterpolation::BrdfInterpolation(const Table& t, const std::string& file) {
  const std::string where = file + ": table '" + t.name + "'";
  auto refuse = [&](const std::string& why) { throw ConfigError(where, "", why); };
  if (t.quantity != "brdf") refuse("is a " + t.quantity + " table, not a brdf table");
  std::vector<std::string> names;
  for (const Axis& a : t.axes) names.push_back(a.name);
  const bool channel = names.size() == 5 && names[4] == "channel";
  if (!(names.size() >= 4 && names[0] == "theta_i" && names[1] == "phi_i" && names[2] == "theta_o" && names[3] == "phi" &&
        (names.size() == 4 || channel)))
    refuse("axes must be theta_i, phi_i, theta_o, phi[, channel]");
  ti_ = positions(t.axes[0], refuse);  // (theta_i given as bins: at their centres; it read past the points)
  to_ = positions(t.axes[2], refuse);
  ph_ = positions(t.axes[3], refuse);
  positions(t.axes[1], refuse);  // phi_i: checked only (one point, below)
  if (t.axes[1].size() != 1) refuse("has " + std::to_string(t.axes[1].size()) + " incident azimuths; MERL holds isotropic BRDFs (one phi_i)");
  if (t.axes[3].values.back() - t.axes[3].values.front() > kPi + 1e-9)
    refuse("is anisotropic (phi over [0, 2 pi), from an anisotropic medium); MERL holds isotropic BRDFs (phi over [0, pi])");
  channels_ = channel ? static_cast<int>(t.axes[4].size()) : 1;
  if (channels_ != 1 && channels_ != 3) refuse("has " + std::to_string(channels_) + " channels (1 or 3 allowed)");
  double gap = 0;
  for (std::size_t k = 1; k < ti_.size(); ++k) gap = std::max(gap, ti_[k] - ti_[k - 1]);
  const double d = kPi / 180;
  if (ti_.size() < 2 || ti_.front() > 5 * d + 1e-12 || ti_.back() < 75 * d - 1e-12 || gap > 15 * d + 1e-12)
    refuse("is too coarse for export: theta_i must run from <= 5 deg to >= 75 deg in steps <= 15 deg (has " +
           std::to_string(ti_.size()) + " angles, " + deg(ti_.front()) + " to " + deg(ti_.back()) + " deg, largest step " +
           deg(gap) + " deg)");
  if (to_.size() < 8) refuse("is too coarse for export: at least 8 theta_o bins are needed (has " + std::to_string(to_.size()) + ")");
  if (ph_.size() < 8 || t.axes[3].values.back() - t.axes[3].values.front() < kPi - 1e-9)
    refuse("is too coarse for export: at least 8 phi bins over [0, pi] are needed (has " + std::to_string(ph_.size()) + ")");
  // MERL's phi_d folds into [0, pi]: an axis elsewhere (e.g. [-pi, 0]) would be
  // held at its last value everywhere.
  if (!(std::fabs(t.axes[3].values.front()) <= 1e-9 && std::fabs(t.axes[3].values.back() - kPi) <= 1e-9))
    refuse("has phi over [" + deg(t.axes[3].values.front()) + ", " + deg(t.axes[3].values.back()) +
           "] deg; MERL needs [0, 180] deg");
  values_ = t.values();
  // A NaN (a cell some batch left empty), infinite or negative value would be
  // spread over the MERL cells around it (MERL reads negative as below the horizon).
  for (std::size_t n = 0; n < values_.size(); ++n)
    if (!(values_[n] >= 0 && std::isfinite(values_[n]))) {
      char v[32];
      std::snprintf(v, sizeof v, "%.17g", values_[n]);
      refuse("cell " + std::to_string(n) + " holds " + v +
             "; a MERL file needs finite values >= 0 (NaN: a batch had no sample there; simulate more samples)");
    }
}

double BrdfInterpolation::operator()(double theta_i, double theta_o, double phi, int c) const {
  if (!(std::cos(theta_i) > 0) || !(std::cos(theta_o) > 0)) return 0;
  phi = std::fabs(std::remainder(phi, 2 * kPi));  // fold into [0, pi]
  if (channels_ == 1) c = 0;
  std::size_t a, b, e;
  double wa, wb, we;
  locate(ti_, theta_i, a, wa);
  locate(to_, theta_o, b, wb);
  locate(ph_, phi, e, we);
  const std::size_t na = ti_.size(), nb = to_.size(), ne = ph_.size();
  auto at = [&](std::size_t i, std::size_t j, std::size_t k) {
    return values_[((i * nb + j) * ne + k) * channels_ + c];  // phi_i axis has size 1
  };
  double f = 0;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) {
        const double w = (x ? wa : 1 - wa) * (y ? wb : 1 - wb) * (z ? we : 1 - we);
        if (w == 0) continue;
        f += w * at(std::min(a + x, na - 1), std::min(b + y, nb - 1), std::min(e + z, ne - 1));
      }
  return f;
}

}  // namespace mcref
