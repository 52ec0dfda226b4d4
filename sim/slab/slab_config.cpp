// [geometry] kind = "slab": parsing and validation (issue #4).
//
//   [geometry]
//   kind = "slab"
//   substrate = "none" | "lambertian" | "conductor" | "rough_conductor"   (default none)
//   substrate_albedo = 1.0 | [r, g, b]          lambertian (default 1)
//   substrate_eta = 0.2, substrate_k = 3.9       conductors: complex IOR, one value or [r, g, b]
//   substrate_alpha                             rough_conductor (GGX), required
//   delta_transmission = true                   record the unscattered transmission
//   walk = "scalar" | "wave"                    path by path, or data-parallel (up to 4 layers, either backend)
//   estimator = "analog" | "next_event" | "next_event_mis"   escapes tallied where they happen, or by
//                                               their probability at every event (scalar walk)
//   backend = "homogeneous" | "openvdb"         free-flight sampling (default homogeneous)
//   tile = 1.0, lateral_voxels = 4, depth_voxels = 32   openvdb grid
//   density_vdb = "slab.vdb"                    openvdb: every layer's density from a file
//                                               (sim/slab/density_vdb.h; no density keys in the layers)
//   [[geometry.layer]]                           top to bottom, at least one
//   phase = "sggx_surface" | "sggx_fiber" | "hg" | "isotropic" | "lambert_sphere"
//   thickness = 1.0                              T
//   density = 1.0  or  optical_thickness = 5     rho, or T rho (then rho = value / T)
//   alpha = 0.5                                  SGGX roughness
//   orientation = [x, y, z]  or  orientation_deg = [theta, phi]   SGGX omega_p
//   g = 0.3                                      hg
//   albedo = 0.9 | [r, g, b]                     gamma
//   f0 = 1 | [r, g, b]                           Schlick f0 of the flakes
//   profile = "constant" | "linear" | "table"    depth profile of density
//   profile_top, profile_bottom                  linear: multipliers at the top / bottom
//   profile_table = [...]                        table: multipliers at equally spaced depths
#include <cmath>

#include "sim/experiment/experiment_parts.h"
#include "sim/files/input_file.h"
#include "sim/slab/density_vdb.h"
#include "sim/slab/wave_walk.h"

namespace mcref {

namespace {

Rgb read_rgb(TomlReader& r, const std::string& key, Range range, double fallback) {
  const std::vector<double> v = r.numbers(key, range, std::vector<double>{fallback});
  if (v.size() == 1) return Rgb(v[0]);
  if (v.size() != 3) r.fail(key, "takes one number or three (RGB), each in " + range.text());
  return {v[0], v[1], v[2]};
}

DensityProfile read_profile(TomlReader& r) {
  DensityProfile p;
  const std::string kind = r.string("profile", {"constant", "linear", "table"}, std::string("constant"));
  const Range mult{0, 1e6, false, false};
  if (kind == "linear") {
    p.kind = DensityProfile::Kind::kLinear;
    p.top = r.number("profile_top", mult);
    p.bottom = r.number("profile_bottom", mult);
  } else if (kind == "table") {
    p.kind = DensityProfile::Kind::kTable;
    p.table = r.numbers("profile_table", mult);
    if (p.table.size() < 2) r.fail("profile_table", "needs at least 2 values, each in " + mult.text());
  }
  if (!(p.max() > 0)) r.fail("profile", "the density profile is zero everywhere; give a positive multiplier");
  return p;
}

// rho and its depth profile, from the layer's keys.
void read_density(TomlReader& r, SlabLayer& l) {
  l.profile = read_profile(r);
  if (r.has("density") && r.has("optical_thickness"))
    r.fail("optical_thickness", "give either density or optical_thickness, not both");
  if (r.has("optical_thickness")) {
    const double tau = r.number("optical_thickness", {0, 1e6, false, false});
    l.density = tau / (l.thickness * l.profile.mean());  // so that T rho mean(profile) = tau
    // The density key's bound (a tiny thickness made rho infinite: every flight of length 0).
    if (!(l.density <= 1e9))
      r.fail("optical_thickness", "= " + exact_text(tau) + " over thickness " + exact_text(l.thickness) + " gives density " +
                                      exact_text(l.density) + ", more than 1e9; use a larger thickness");
  } else {
    l.density = r.number("density", {0, 1e9, false, false}, 1.0);
    // The walk's cost grows with the optical thickness: the same bound as optical_thickness.
    const double tau = l.optical_thickness();
    if (!(tau <= 1e6))
      r.fail("density", "gives an optical thickness T rho mean(profile) of " + std::to_string(tau) +
                            ", more than 1e6; lower density or thickness");
  }
}

SlabLayer read_layer(TomlReader& r, bool density_from_file) {
  SlabLayer l;
  const std::string phase = r.string("phase", {"sggx_surface", "sggx_fiber", "hg", "isotropic", "lambert_sphere"});
  l.phase = phase == "sggx_surface" ? SlabPhase::kSggxSurface
            : phase == "sggx_fiber" ? SlabPhase::kSggxFiber
            : phase == "hg"         ? SlabPhase::kHenyeyGreenstein
            : phase == "isotropic"  ? SlabPhase::kIsotropic
                                    : SlabPhase::kLambertSphere;
  l.thickness = r.number("thickness", {0, 1e9, true, false}, 1.0);
  if (density_from_file) {
    for (const char* key : {"density", "optical_thickness", "profile", "profile_top", "profile_bottom", "profile_table"})
      if (r.has(key)) r.fail(key, "the layer's density comes from geometry.density_vdb; remove this key");
  } else {
    read_density(r, l);
  }
  if (l.is_sggx()) {
    // S has eigenvalues 1 and alpha^2 (SpongeCake Eq. 3-4): below 1e-4 a tilted
    // S is no longer positive definite, or sigma no longer accurate, in double precision.
    l.alpha = r.number("alpha", {1e-4, 1e3, false, false});
    if (r.has("orientation") && r.has("orientation_deg"))
      r.fail("orientation_deg", "give either orientation or orientation_deg, not both");
    if (r.has("orientation")) {
      const std::vector<double> v = r.numbers("orientation", {-1e6, 1e6, false, false});
      if (v.size() != 3) r.fail("orientation", "takes a direction [x, y, z]");
      const Vec3 d{v[0], v[1], v[2]};
      if (!(length(d) > 0)) r.fail("orientation", "must be a non-zero direction");
      l.orientation = normalize(d);
    } else if (r.has("orientation_deg")) {
      const std::vector<double> v = r.numbers("orientation_deg", {-360, 360, false, false});
      if (v.size() != 2) r.fail("orientation_deg", "takes [theta, phi] in degrees, each in [-360, 360]");
      l.orientation = spherical_direction(deg_to_rad(v[0]), deg_to_rad(v[1]));
    }
    l.f0 = read_rgb(r, "f0", {0, 1, false, false}, 1.0);
  }
  if (l.phase == SlabPhase::kHenyeyGreenstein) l.g = r.number("g", {-1, 1, true, true});
  l.albedo = read_rgb(r, "albedo", {0, 1, false, false}, 1.0);
  return l;
}

}  // namespace

void read_slab_geometry(TomlReader& g, Experiment& e) {
  SlabGeometry& s = e.slab;
  s.configured = true;
  const auto layers = g.tables("layer");
  if (layers.empty()) g.fail("layer", "at least one [[geometry.layer]] table is required");
  if (g.has("density_vdb") && g.string("backend", {"homogeneous", "openvdb"}, std::string("homogeneous")) != "openvdb")
    g.fail("density_vdb", "needs backend = \"openvdb\"");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    TomlReader r(*layers[i], g.file(), g.full("layer." + std::to_string(i)));
    s.layers.push_back(read_layer(r, g.has("density_vdb")));
    r.finish();
  }
  const std::string sub = g.string("substrate", {"none", "lambertian", "conductor", "rough_conductor"}, std::string("none"));
  SlabSubstrate& b = s.substrate;
  if (sub == "lambertian") {
    b.kind = SlabSubstrate::Kind::kLambertian;
    b.albedo = read_rgb(g, "substrate_albedo", {0, 1, false, false}, 1.0);
  } else if (sub == "conductor" || sub == "rough_conductor") {
    b.kind = sub == "conductor" ? SlabSubstrate::Kind::kConductor : SlabSubstrate::Kind::kRoughConductor;
    b.eta = read_rgb(g, "substrate_eta", {0, 100, true, false}, 0.2);
    b.k = read_rgb(g, "substrate_k", {0, 100, false, false}, 3.9);
    if (sub == "rough_conductor") b.alpha = g.number("substrate_alpha", {0, 10, true, false});
  }
  // Light reaches nothing under the stack but the substrate: no unscattered transmission to record.
  if (b.kind != SlabSubstrate::Kind::kNone && g.has("delta_transmission"))
    g.fail("delta_transmission", "has no effect over a substrate (nothing is transmitted); remove it");
  s.delta_transmission = g.boolean("delta_transmission", true);
  s.grid.openvdb = g.string("backend", {"homogeneous", "openvdb"}, std::string("homogeneous")) == "openvdb";
  s.grid.tile = g.number("tile", {0, 1e9, true, false}, 1.0);
  s.grid.lateral_voxels = static_cast<int>(g.integer("lateral_voxels", 1, 4096, 4));
  s.grid.depth_voxels = static_cast<int>(g.integer("depth_voxels", 1, 1 << 20, 32));
  // (The grid keys serve export-vdb too, whatever the backend.)
  if (static_cast<double>(s.grid.lateral_voxels + 1) * (s.grid.lateral_voxels + 1) * (s.grid.depth_voxels + 1) *
          s.layers.size() > 2e8)
    g.fail("depth_voxels", "the grids would hold more than 2e8 voxels; use fewer lateral_voxels or depth_voxels");
  // The voxels are linear in depth between their planes: a table's breakpoint
  // between two planes would be cut (and the optical thickness missed).
  for (std::size_t i = 0; i < s.layers.size(); ++i) {
    const DensityProfile& p = s.layers[i].profile;
    if (!s.grid.openvdb || g.has("density_vdb") || p.kind != DensityProfile::Kind::kTable) continue;
    const int intervals = static_cast<int>(p.table.size()) - 1;
    if (s.grid.depth_voxels % intervals != 0)
      throw ConfigError(e.file, g.full("layer." + std::to_string(i) + ".profile_table"),
                        "has " + std::to_string(intervals) + " intervals, which must divide geometry.depth_voxels = " +
                            std::to_string(s.grid.depth_voxels) + " (the voxels are linear between their planes: " +
                            "a breakpoint between two planes is cut); use depth_voxels = " +
                            std::to_string((s.grid.depth_voxels / intervals + 1) * intervals) + ", or another multiple of " +
                            std::to_string(intervals));
  }
  if (g.has("density_vdb")) {
    s.grid.density_vdb = g.any_string("density_vdb");
    InputFile in{path_beside(e.file, s.grid.density_vdb), ""};
    in.digest = volume::read_density_vdb(in.path, g.file(), g.full("density_vdb"), s);
    // The provenance names its content, with the path as given (the same from any working directory).
    e.text += input_provenance(g.full("density_vdb"), s.grid.density_vdb, in.digest);
    e.inputs.push_back(in);
  }
  s.wave_walk = g.string("walk", {"scalar", "wave"}, std::string("scalar")) == "wave";
  if (s.wave_walk)
    if (const std::string why = volume::wave_walk_unsupported(s); !why.empty()) g.fail("walk", why);
  const std::string estimator = g.string("estimator", {"analog", "next_event", "next_event_mis"}, std::string("analog"));
  s.estimator = estimator == "analog"       ? SlabEstimator::kAnalog
                : estimator == "next_event" ? SlabEstimator::kNextEvent
                                            : SlabEstimator::kNextEventMis;
  for (std::size_t i = 0; i < s.layers.size(); ++i)
    if (!s.grid.openvdb && s.layers[i].profile.kind != DensityProfile::Kind::kConstant)
      throw ConfigError(e.file, "geometry.layer." + std::to_string(i) + ".profile",
                        "a depth profile needs backend = \"openvdb\" (the homogeneous backend takes constant density)");
  e.isotropic = true;
  for (const SlabLayer& l : s.layers) e.isotropic = e.isotropic && l.azimuthally_symmetric();
}

}  // namespace mcref
