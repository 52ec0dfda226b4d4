// [material] of micrograin transport: grain and base micro-BRDFs (issue #3).
//   [material.grain] / [material.base]:
//     type   = "black" | "lambertian" | "conductor" | "rough_conductor" | "diffuse_specular"
//     albedo = K_d, one number or [r, g, b] in [0, 1]      (lambertian, diffuse_specular; default 0.8)
//     preset = "gold" | "copper", or eta = .. and kappa = .. (one number or [r, g, b])  (conductors)
//     ior    = interface index in (1, 4]                   (diffuse_specular; default 1.5)
//     alpha  = GGX roughness in (0, 4]                     (rough_conductor; default 0.3)
#include "models/microfacet/fresnel.h"
#include "sim/experiment/experiment_parts.h"

namespace mcref {

namespace {

Rgb read_rgb(TomlReader& r, const std::string& key, Range range, std::optional<double> fallback) {
  std::vector<double> v = fallback ? r.numbers(key, range, std::vector<double>{*fallback}) : r.numbers(key, range);
  if (v.size() == 1) return Rgb(v[0]);
  if (v.size() != 3) r.fail(key, "takes one number or three (r, g, b), each in " + range.text());
  return {v[0], v[1], v[2]};
}

MicroBrdf read_micro_brdf(const toml::table& t, const std::string& file, const std::string& prefix) {
  TomlReader r(t, file, prefix);
  MicroBrdf b;
  const std::string type = r.string("type", {"black", "lambertian", "conductor", "rough_conductor", "diffuse_specular"});
  const Range unit{0, 1, false, false};
  if (type == "black") {
    b.type = MicroBrdf::Type::Black;
  } else if (type == "lambertian") {
    b.type = MicroBrdf::Type::Lambertian;
    b.albedo = read_rgb(r, "albedo", unit, 0.8);
  } else if (type == "diffuse_specular") {
    b.type = MicroBrdf::Type::DiffuseSpecular;
    b.albedo = read_rgb(r, "albedo", unit, 0.8);
    b.ior = r.number("ior", {1, 4, true, false}, 1.5);
  } else {
    b.type = type == "conductor" ? MicroBrdf::Type::Conductor : MicroBrdf::Type::RoughConductor;
    if (r.has("preset")) {
      if (r.has("eta") || r.has("kappa")) r.fail("preset", "give either preset or eta and kappa, not both");
      const std::string p = r.string("preset", {"gold", "copper"});
      const micrograin::ComplexIorRgb& c = p == "gold" ? micrograin::kGold : micrograin::kCopper;
      b.eta = {c.eta[0], c.eta[1], c.eta[2]};
      b.kappa = {c.kappa[0], c.kappa[1], c.kappa[2]};
    } else {
      if (!r.has("eta") || !r.has("kappa"))
        r.fail(r.has("eta") ? "kappa" : "eta", "is required for a " + type + " (or preset = \"gold\" / \"copper\")");
      b.eta = read_rgb(r, "eta", {0, 100, true, false}, std::nullopt);
      b.kappa = read_rgb(r, "kappa", {0, 100, false, false}, std::nullopt);
    }
    if (b.type == MicroBrdf::Type::RoughConductor) b.alpha = r.number("alpha", {0, 4, true, false}, 0.3);
  }
  r.finish();
  return b;
}

}  // namespace

void read_micrograin_materials(const toml::table* table, Experiment& e) {
  if (!table) return;
  TomlReader m(*table, e.file, "material");
  const toml::table* grain = m.table("grain");
  const toml::table* base = m.table("base");
  if (!grain) m.fail("grain", "is required: a [material.grain] table with type = \"lambertian\", \"conductor\", ...");
  if (!base) m.fail("base", "is required: a [material.base] table with type = \"lambertian\", \"conductor\", ...");
  e.materials.grain = read_micro_brdf(*grain, e.file, "material.grain");
  e.materials.base = read_micro_brdf(*base, e.file, "material.base");
  e.materials.configured = true;
  m.finish();
}

}  // namespace mcref
