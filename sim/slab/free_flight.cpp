#include "sim/slab/free_flight.h"

#include <cmath>

#include "sim/slab/density_grid.h"

namespace mcref::volume {

namespace {

// The tracking loop; `majorant(l, d)` is the (majorant) extinction of layer l
// along d, `accept(p, k)` decides whether a tentative collision in layer k is
// real (always, for homogeneous layers at their own density).
template <class Majorant, class Accept>
Flight track(const std::vector<MediumLayer>& layers, Photon& p, Rng& rng, Majorant majorant, Accept accept) {
  const int n = static_cast<int>(layers.size());
  const double rate = -p.d.z;  // d(depth)/ds
  double tau = -std::log1p(-rng.uniform());
  for (;;) {
    const MediumLayer& l = layers[p.layer];
    const double mu_t = majorant(l, p.d);
    const double dist = rate > 0 ? (l.bottom - p.depth) / rate : rate < 0 ? (l.top - p.depth) / rate : INFINITY;
    const double optical = mu_t > 0 ? mu_t * dist : 0.0;
    if (tau < optical) {
      p.advance(tau / mu_t);
      if (accept(p, p.layer)) return Flight::kCollision;
      tau = -std::log1p(-rng.uniform());  // null collision: memoryless restart
      continue;
    }
    if (!std::isfinite(dist)) return Flight::kLost;  // horizontal in an empty layer (measure zero)
    tau -= optical;
    p.advance(dist);
    if (rate > 0) {
      p.depth = l.bottom;
      if (++p.layer == n) {
        p.layer = n - 1;
        return Flight::kExitBottom;
      }
    } else {
      p.depth = l.top;
      if (--p.layer < 0) {
        p.layer = 0;
        return Flight::kExitTop;
      }
    }
  }
}

class HomogeneousFlight final : public FreeFlight {
 public:
  explicit HomogeneousFlight(const SlabMedium& m) : m_(m) {}
  Flight fly(Photon& p, Rng& rng) override {
    return track(
        m_.layers(), p, rng, [](const MediumLayer& l, Vec3 d) { return l.density * l.phase->sigma(d); },
        [](const Photon&, int) { return true; });
  }

 private:
  const SlabMedium& m_;
};

class GridFlight final : public FreeFlight {
 public:
  explicit GridFlight(const SlabMedium& m) : m_(m), lookup_(*m.grids()) {}
  Flight fly(Photon& p, Rng& rng) override {
    have_s_ = false;
    return track(
        m_.layers(), p, rng,
        [](const MediumLayer& l, Vec3 d) { return l.sggx_grid ? l.extinction_majorant : l.majorant * l.phase->sigma(d); },
        [&](const Photon& q, int k) {
          const MediumLayer& l = m_.layers()[k];
          if (!l.sggx_grid) return rng.uniform() * l.majorant < lookup_.density(k, q.x, q.y, q.depth);
          sggx::Mat3 S;
          const double rho = lookup_.density_and_sggx(k, q.x, q.y, q.depth, S);
          const double sigma = std::sqrt(std::fmax(0.0, sggx::quadratic_form(S, q.d)));
          if (!(rng.uniform() * l.extinction_majorant < rho * sigma)) return false;
          s_ = sggx::from_matrix(S);  // the event's S: Cholesky factor and inverse for the sampler
          have_s_ = true;
          return true;
        });
  }
  ScatterSample scatter(const MediumLayer& layer, int k, Vec3 wi, Rng& rng) override {
    if (!have_s_) return layer.phase->sample(wi, rng);
    const SlabLayer& l = m_.geometry().layers[k];
    return sample_sggx_flakes(s_, l.albedo, l.f0, wi, rng);
  }
  double lateral_period() const override { return m_.geometry().grid.tile; }

 private:
  const SlabMedium& m_;
  GridLookup lookup_;
  sggx::Sggx s_;
  bool have_s_ = false;
};

}  // namespace

std::unique_ptr<FreeFlight> make_homogeneous_flight(const SlabMedium& m) { return std::make_unique<HomogeneousFlight>(m); }

std::unique_ptr<FreeFlight> make_flight(const SlabMedium& m) {
  if (m.grids()) return std::make_unique<GridFlight>(m);
  return make_homogeneous_flight(m);
}

}  // namespace mcref::volume
