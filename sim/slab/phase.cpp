#include "sim/slab/phase.h"

#include <algorithm>
#include <cmath>

#include "models/core/warp.h"
#include "models/lambert_sphere/phase_function.h"
#include "models/lambert_sphere/phase_sampling.h"
#include "models/sggx/flake_phase.h"
#include "models/sggx/hg_phase.h"
#include "models/sggx/sggx_distribution.h"

namespace mcref::volume {

namespace {

// Specular two-sided SGGX flakes: f_p = D(h) / (4 sigma(wi)) (Eq. 4); a visible
// normal m of wi is sampled and wi reflected about it; F = gamma Schlick(f0, wi.m).
class SggxFlakes final : public PhaseFunction {
 public:
  explicit SggxFlakes(const SlabLayer& l)
      : s_(l.phase == SlabPhase::kSggxSurface ? sggx::surface_like(l.alpha, l.orientation)
                                              : sggx::fiber_like(l.alpha, l.orientation)),
        albedo_(l.albedo), f0_(l.f0), max_sigma_(std::max(1.0, l.alpha)) {}
  double sigma(Vec3 w) const override { return sggx::projected_area(s_, w); }
  double max_sigma() const override { return max_sigma_; }
  double eval(Vec3 wi, Vec3 wo) const override { return sggx::specular_flake_phase(s_, wi, wo); }
  ScatterSample sample(Vec3 wi, Rng& rng) const override { return sample_sggx_flakes(s_, albedo_, f0_, wi, rng); }
  Rgb albedo(Vec3 wi, Vec3 wo) const override {
    const Vec3 h = normalize(wi + wo);
    return {sggx::flake_reflectance(albedo_.r, f0_.r, wi, h), sggx::flake_reflectance(albedo_.g, f0_.g, wi, h),
            sggx::flake_reflectance(albedo_.b, f0_.b, wi, h)};
  }

 private:
  sggx::Sggx s_;
  Rgb albedo_, f0_;
  double max_sigma_;
};

class HenyeyGreenstein final : public PhaseFunction {
 public:
  explicit HenyeyGreenstein(const SlabLayer& l) : g_(l.g), albedo_(l.albedo) {}
  double eval(Vec3 wi, Vec3 wo) const override { return sggx::hg_phase(g_, wi, wo); }
  ScatterSample sample(Vec3 wi, Rng& rng) const override {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const sggx::PhaseSample p = sggx::sample_hg_phase(g_, 1.0, wi, u1, u2);
    return {p.wo, albedo_, p.valid};
  }
  Rgb albedo(Vec3, Vec3) const override { return albedo_; }

 private:
  double g_;
  Rgb albedo_;
};

class Isotropic final : public PhaseFunction {
 public:
  explicit Isotropic(const SlabLayer& l) : albedo_(l.albedo) {}
  double eval(Vec3, Vec3) const override { return 1 / (4 * kPi); }
  ScatterSample sample(Vec3, Rng& rng) const override {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    return {sample_uniform_sphere(u1, u2), albedo_, true};
  }
  Rgb albedo(Vec3, Vec3) const override { return albedo_; }

 private:
  Rgb albedo_;
};

// d'Eon 2021 Eq. 1 (mu between the propagation directions), exact sampler Eq. 5.
class LambertSphere final : public PhaseFunction {
 public:
  explicit LambertSphere(const SlabLayer& l) : albedo_(l.albedo) {}
  double eval(Vec3 wi, Vec3 wo) const override { return lambert_sphere::phase_function(dot(-wi, wo)); }
  ScatterSample sample(Vec3 wi, Rng& rng) const override {
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform();
    const double mu = lambert_sphere::sample_phase_cosine_exact(u1, u2, u3);
    return {lambert_sphere::scattered_direction(-wi, mu, u4), albedo_, true};
  }
  Rgb albedo(Vec3, Vec3) const override { return albedo_; }

 private:
  Rgb albedo_;
};

}  // namespace

ScatterSample sample_sggx_flakes(const sggx::Sggx& s, const Rgb& albedo, const Rgb& f0, Vec3 wi, Rng& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform();
  const Vec3 m = sggx::sample_visible_normal(s, wi, u1, u2);
  const double c = dot(wi, m);
  ScatterSample r;
  r.wo = normalize(m * (2 * c) - wi);
  const double ac = std::fabs(c);
  r.weight = {albedo.r * sggx::schlick(f0.r, ac), albedo.g * sggx::schlick(f0.g, ac), albedo.b * sggx::schlick(f0.b, ac)};
  r.valid = c > 0;
  return r;
}

std::unique_ptr<PhaseFunction> make_phase(const SlabLayer& l) {
  switch (l.phase) {
    case SlabPhase::kSggxSurface:
    case SlabPhase::kSggxFiber: return std::make_unique<SggxFlakes>(l);
    case SlabPhase::kHenyeyGreenstein: return std::make_unique<HenyeyGreenstein>(l);
    case SlabPhase::kIsotropic: return std::make_unique<Isotropic>(l);
    case SlabPhase::kLambertSphere: break;
  }
  return std::make_unique<LambertSphere>(l);
}

}  // namespace mcref::volume
