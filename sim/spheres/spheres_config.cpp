// [geometry] kind = "spheres": parsing and validation (issue #5).
//
//   [geometry]
//   kind = "spheres"
//   albedo = 0.8 | [r, g, b]            Lambertian albedo c of the spheres, in [0, 1]
//   volume_fraction = 0.07              f, in (0, 1) (rsa: at most 0.36)
//   placement = "poisson" | "rsa" | "volumetric"   (default poisson)
//   radius = 1.0                        r in [1e-100, 1e100] (units only: a half-space BRDF has no
//                                       scale; the bound keeps the depth attribute, depth r, finite)
//   transmission_threshold = 1e-4       slab deep enough to transmit less than this
//   depth_mfp = 40                      or: the depth itself, in mean free paths 1/(n pi r^2)
//   tile = 100                          lateral period in radii (explicit placements)
#include <cmath>
#include <cstdio>
#include <limits>

#include "sim/experiment/experiment_parts.h"

namespace mcref {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxDepthMfp = 1e5;
constexpr double kMaxSpheres = 2e7;

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}
}  // namespace

void read_spheres_geometry(TomlReader& g, Experiment& e) {
  SpherePacking& p = e.spheres;
  p.configured = true;
  const std::vector<double> c = g.numbers("albedo", {0, 1, false, false});
  if (c.size() == 1) p.albedo = Rgb(c[0]);
  else if (c.size() == 3) p.albedo = {c[0], c[1], c[2]};
  else g.fail("albedo", "takes one number or three (RGB), each in [0, 1]");
  const std::string placement = g.string("placement", {"poisson", "rsa", "volumetric"}, std::string("poisson"));
  p.placement = placement == "rsa"          ? SpherePlacement::rsa
                : placement == "volumetric" ? SpherePlacement::volumetric
                                            : SpherePlacement::poisson;
  p.volume_fraction = g.number("volume_fraction", {0, 1, true, true},
                               p.placement == SpherePlacement::volumetric ? std::optional<double>(0.07) : std::nullopt);
  if (p.placement == SpherePlacement::rsa && p.volume_fraction > kRsaMaxVolumeFraction)
    g.fail("volume_fraction", "is " + format("%g", p.volume_fraction) +
                                  "; random sequential addition jams at ~0.384 and approaches it too slowly, "
                                  "so at most " + format("%g", kRsaMaxVolumeFraction) + " is allowed with placement = \"rsa\"");
  p.radius = g.number("radius", {1e-100, 1e100, false, false}, 1.0);
  p.transmission_threshold = g.number("transmission_threshold", {0, 0.5, true, false}, 1e-4);
  if (g.has("depth_mfp")) {
    p.depth_mfp = g.number("depth_mfp", {0, kMaxDepthMfp, true, false});
  } else if (p.depth_in_mfp() > 5000) {
    g.fail("transmission_threshold", "needs a slab ~" + format("%.0f", p.depth_in_mfp()) +
                                         " mean free paths deep at albedo " + format("%g", p.albedo.max()) +
                                         " (from its asymptotic decay rate); set depth_mfp or raise the threshold");
  }
  // At most 1000: x, y go to Embree in single precision (a step of 6e-5 radii at
  // 1000; at 1e4, 1e-3, and grazing hits were missed).
  p.tile = g.number("tile", {8, 1000, false, false}, 100.0);
  const double mfp = 1 / p.extinction();  // in radii
  if (p.placement != SpherePlacement::volumetric && mfp > kMaxTilesPerFreeFlight * p.tile)
    g.fail("volume_fraction", "is " + format("%g", p.volume_fraction) + ": the mean free path, " + format("%.3g", mfp) +
                                  " radii, is " + format("%.3g", mfp / p.tile) + " tiles, so every free flight would wrap the tile " +
                                  "that often (at most " + format("%g", kMaxTilesPerFreeFlight) + "). Raise tile or volume_fraction, " +
                                  "or use placement = \"volumetric\", the same medium's f -> 0 limit");
  if (p.placement != SpherePlacement::volumetric && p.expected_count() > kMaxSpheres)
    g.fail("tile", "gives ~" + format("%.3g", p.expected_count()) + " spheres (depth " +
                       format("%.0f", p.depth()) + " radii); at most 2e7 are allowed: reduce tile or depth_mfp");
  e.isotropic = true;
}

}  // namespace mcref
