#include "validate/micrograin/simulated_pore_base.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <sstream>

#include "models/core/statistics.h"
#include "models/core/warp.h"
#include "sim/micrograin/estimator.h"
#include "sim/micrograin/micrograin_field.h"
#include "sim/tally/brdf_tally.h"

namespace mcref {

namespace {

constexpr std::uint64_t kPorePoints = 40000;                // per incident direction
constexpr std::uint64_t kSeed = 0x706f72655f766973ULL;      // "pore_vis": field and streams
constexpr int kAlbedoDirections = 16;                        // cosine-weighted o per pore point
// V_p is an ensemble property: one field, but a wide one (10^4 to 10^5
// grains), so that its own realisation departs from the mean by < 1 %.
constexpr double kMinTile = 400;  // grain radii

// A uniform point of the base that lies in a pore (under no grain).
Vec3 pore_point(const MicrograinField& f, Rng& rng) {
  for (;;) {
    const Vec3 p{rng.uniform() * f.unit_side_x(), rng.uniform() * f.unit_side_y(), 0.0};
    if (!f.under_grain(p.x, p.y)) return p;
  }
}

bool visible(const MicrograinField& f, Vec3 p, Vec3 w) {
  return !f.occluded_unit(p, unit_direction(f, w), MicrograinField::kNoGrain);
}

PoreBase evaluate(const Table& t, const Experiment& ex, const BaseReflection& base) {
  MicrograinGeometry geometry = ex.micrograin;
  geometry.tile = std::max(geometry.tile, kMinTile);
  const MicrograinField f(geometry, kSeed);
  const double pores = 1 - ex.micrograin.tau0;
  const double n = static_cast<double>(kPorePoints);
  PoreBase out{std::vector<double>(t.cells(), NAN), std::vector<double>(t.cells(), NAN)};
  const Axis &ti = t.axes[0], &pi = t.axes[1];
  const bool delta_only = is_delta_table(t.name);
  std::uint64_t dir = 0;
  for (std::size_t a = 0; a < ti.size(); ++a)
    for (std::size_t b = 0; b < pi.size(); ++b, ++dir) {
      const Vec3 wi = spherical_direction(ti.values[a], pi.values[b]);
      const std::uint64_t key = stream_seed({kSeed, dir});
      if (t.quantity == "brdf") {
        const Axis &to = t.axes[2], &ph = t.axes[3];
        const std::size_t np = ph.size();
        // Per cell and channel: the sum over pore points, then the sum of squares.
        const std::size_t m = to.size() * np * 3;
        const Sums s = run_chunks(kPorePoints, 2 * m, key, [&](Rng& rng, std::uint64_t count, Sums& acc) {
          for (std::uint64_t k = 0; k < count; ++k) {
            const Vec3 p = pore_point(f, rng);
            if (!visible(f, p, wi)) continue;
            for (std::size_t c = 0; c < to.size(); ++c)
              for (std::size_t d = 0; d < np; ++d) {
                // o cosine-weighted in the cell: mu^2 uniform, phi uniform.
                const double m0 = std::cos(to.upper(c)), m1 = std::cos(to.lower(c));
                const double mu = std::sqrt(m0 * m0 + rng.uniform() * (m1 * m1 - m0 * m0));
                const double phi = pi.values[b] + ph.lower(d) + rng.uniform() * (ph.upper(d) - ph.lower(d));
                const Vec3 wo = spherical_direction(std::acos(mu), phi);
                if (!visible(f, p, wo)) continue;
                for (int ch = 0; ch < 3; ++ch) {
                  const double v = base.brdf(ch, wi, wo);
                  acc[(c * np + d) * 3 + ch] += v;
                  acc[m + (c * np + d) * 3 + ch] += v * v;
                }
              }
          }
        });
        for (std::size_t c = 0; c < to.size(); ++c)
          for (std::size_t d = 0; d < np; ++d)
            for (std::size_t ch = 0; ch < 3; ++ch) {
              const std::size_t j = (c * np + d) * 3 + ch, cell = t.index({a, b, c, d, ch});
              out.values[cell] = pores * s[j] / n;
              out.stderrs[cell] = pores * stderr_of_mean(s[j], s[m + j], n);
            }
      } else {  // albedo or delta: the order1_base and total components
        const Vec3 mirror{-wi.x, -wi.y, wi.z};
        bool has_delta = false;
        for (int ch = 0; ch < 3; ++ch) has_delta = has_delta || base.delta_energy(ch, wi) > 0;
        // Per channel: the sum over pore points of their energy, then its square.
        const Sums s = run_chunks(kPorePoints, 6, key, [&](Rng& rng, std::uint64_t count, Sums& acc) {
          for (std::uint64_t k = 0; k < count; ++k) {
            const Vec3 p = pore_point(f, rng);
            if (!visible(f, p, wi)) continue;
            double e[3] = {0, 0, 0};
            if (!delta_only)
              for (int j = 0; j < kAlbedoDirections; ++j) {
                const Vec3 wo = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
                if (!visible(f, p, wo)) continue;
                for (int ch = 0; ch < 3; ++ch) e[ch] += kPi * base.brdf(ch, wi, wo) / kAlbedoDirections;
              }
            if (has_delta && visible(f, p, mirror))
              for (int ch = 0; ch < 3; ++ch) e[ch] += base.delta_energy(ch, wi);
            for (int ch = 0; ch < 3; ++ch) {
              acc[ch] += e[ch];
              acc[3 + ch] += e[ch] * e[ch];
            }
          }
        });
        const std::size_t base_component = 1, total = t.axes[2].size() - 1;  // order1_base, total
        for (std::size_t ch = 0; ch < 3; ++ch) {
          const double e = pores * s[ch] / n, se = pores * stderr_of_mean(s[ch], s[3 + ch], n);
          for (const std::size_t comp : {base_component, total}) {
            out.values[t.index({a, b, comp, ch})] = e;
            out.stderrs[t.index({a, b, comp, ch})] = se;
          }
        }
      }
    }
  return out;
}

}  // namespace

const PoreBase& simulated_pore_base(const Table& t, const Experiment& ex, const BaseReflection& base) {
  // Several checks share a table's axes (total and order-1 parts): estimate once.
  std::ostringstream key;
  key.precision(17);
  key << ex.text << '|' << t.quantity << '|' << is_delta_table(t.name);
  for (const Axis& a : t.axes) {
    key << '|' << a.name;
    for (double v : a.values) key << ',' << v;
  }
  // Checks run in parallel: the first to ask estimates, the others wait for
  // its result (the map's futures keep every result alive).
  static std::mutex mutex;
  static std::map<std::string, std::shared_future<PoreBase>> cache;
  std::promise<PoreBase> promise;
  std::shared_future<PoreBase> result;
  bool first = false;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto [it, inserted] = cache.try_emplace(key.str());
    if (inserted) it->second = promise.get_future().share();
    first = inserted;
    result = it->second;
  }
  if (first) {
    try {
      promise.set_value(evaluate(t, ex, base));  // not under the lock: it runs TBB tasks
    } catch (...) {
      promise.set_exception(std::current_exception());
    }
  }
  return result.get();
}

}  // namespace mcref
