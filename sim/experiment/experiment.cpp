#include "sim/experiment/experiment.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "models/core/vec.h"
#include "sim/experiment/experiment_parts.h"
#include "sim/files/input_file.h"

namespace mcref {

namespace {

constexpr std::int64_t kMaxCount = std::int64_t(1) << 40;

std::vector<double> to_radians(std::vector<double> v) {
  for (double& x : v) x = deg_to_rad(x);
  return v;
}

void read_geometry(TomlReader& root, Experiment& e) {
  const toml::table* t = root.table("geometry");
  if (!t) root.fail("geometry", "is required ([geometry] table with kind = \"micrograin\", \"slab\" or \"spheres\")");
  TomlReader g(*t, e.file, "geometry");
  e.kind = g.string("kind", {"micrograin", "slab", "spheres"});
  if (e.kind == "micrograin") read_micrograin_geometry(g, e);
  else if (e.kind == "slab") read_slab_geometry(g, e);
  else read_spheres_geometry(g, e);
  g.finish();
}

}  // namespace

const std::vector<std::string>& known_quantities(const std::string& kind) {
  static const std::vector<std::string> micrograin{"p1", "ndf", "tau_plus", "tau_height", "g1", "pore_visibility", "vndf", "phi_conditional", "brdf"};
  static const std::vector<std::string> slab{"brdf"};
  static const std::vector<std::string> spheres{"brdf", "phase"};
  return kind == "micrograin" ? micrograin : kind == "slab" ? slab : spheres;
}

namespace {

void read_run(TomlReader& root, Experiment& e) {
  const toml::table* t = root.table("run");
  static const toml::table empty;
  TomlReader r(t ? *t : empty, e.file, "run");
  e.run.seed = static_cast<std::uint64_t>(r.integer("seed", 0, std::numeric_limits<std::int64_t>::max(), 1));
  e.run.batches = static_cast<int>(r.integer("batches", 2, 1000000, 16));
  e.run.threads = static_cast<int>(r.integer("threads", 0, 1024, 0));
  r.finish();
}

Measure read_measure(const toml::table& t, const Experiment& e, std::size_t index) {
  TomlReader m(t, e.file, "measure." + std::to_string(index));
  Measure out;
  out.quantity = m.string("quantity", known_quantities(e.kind));
  out.name = m.any_string("name", out.quantity);
  const Range theta{0, 90, false, true}, azimuth{-360, 360, false, false};
  const bool aniso = !e.isotropic;
  out.samples = m.integer("samples", 1, kMaxCount);
  const std::string& q = out.quantity;
  if (q == "p1") {
    out.r_bins = static_cast<int>(m.integer("r_bins", 1, 100000, 60));
    out.r_max = m.number("r_max", {0, 1e4, true, false}, 3.0);
  } else if (q == "ndf") {
    out.theta_m_bins = static_cast<int>(m.integer("theta_m_bins", 1, 10000, 45));
    out.phi_m_bins = static_cast<int>(m.integer("phi_m_bins", 1, 10000, aniso ? 36 : 1));
  } else if (q == "brdf") {
    out.theta_i = to_radians(m.numbers("theta_i_deg", theta));
    out.phi_i = to_radians(m.numbers("phi_i_deg", azimuth, std::vector<double>{0.0}));
    out.theta_o_bins = static_cast<int>(m.integer("theta_o_bins", 1, 10000, 16));
    out.phi_bins = static_cast<int>(m.integer("phi_bins", 1, 10000, aniso ? 36 : 18));
    out.max_order = static_cast<int>(m.integer("max_order", 0, 1000000, 0));
  } else if (q == "phase") {
    out.mu_bins = static_cast<int>(m.integer("mu_bins", 1, 100000, 50));
  } else if (q == "pore_visibility") {
    out.theta_i = to_radians(m.numbers("theta_i_deg", theta));
    out.phi_i = to_radians(m.numbers("phi_i_deg", azimuth, std::vector<double>{0.0}));
    if (out.phi_i.size() != 1) m.fail("phi_i_deg", "takes one azimuth for pore_visibility");
    out.theta_o = to_radians(m.numbers("theta_o_deg", theta));
    out.phi = to_radians(m.numbers("phi_deg", {-360, 360, false, false}, std::vector<double>{0.0, 90.0, 180.0}));
  } else if (q == "phi_conditional") {
    out.theta_i = to_radians(m.numbers("theta_i_deg", theta));  // unit-space angles
    out.theta_m = to_radians(m.numbers("theta_m_deg", theta));
    out.phi_bins = static_cast<int>(m.integer("phi_bins", 1, 10000, 64));
  } else {
    out.theta_i = to_radians(m.numbers("theta_i_deg", theta));
    out.phi_i = to_radians(m.numbers("phi_i_deg", azimuth, std::vector<double>{0.0}));
    if (q == "tau_height") out.h_points = static_cast<int>(m.integer("h_points", 2, 100000, 21));
    if (q == "g1" || q == "vndf") {
      out.theta_m_bins = static_cast<int>(m.integer("theta_m_bins", 1, 10000, 18));
      out.phi_m_bins = static_cast<int>(m.integer("phi_m_bins", 1, 10000, aniso ? 36 : 18));
    }
  }
  m.finish();
  return out;
}

}  // namespace

Experiment parse_experiment(const std::string& text, const std::string& file,
                            const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& err) {
    std::ostringstream s;
    s << "line " << err.source().begin.line << ": " << err.description();
    throw ConfigError(file, "", "TOML syntax error at " + s.str());
  }
  for (const std::string& o : overrides) apply_override(root, o, file);
  Experiment e;
  e.file = file;
  std::ostringstream canonical;
  canonical << root;
  e.text = canonical.str();
  TomlReader r(root, file, "");
  read_geometry(r, e);
  if (e.kind == "micrograin") read_micrograin_materials(r.table("material"), e);
  read_run(r, e);
  const auto measures = r.tables("measure");
  if (measures.empty()) r.fail("measure", "at least one [[measure]] table is required");
  for (std::size_t i = 0; i < measures.size(); ++i) e.measures.push_back(read_measure(*measures[i], e, i));
  // A measure writes tables <name> and <name>_<part> (e.g. g1_conditional,
  // brdf_albedo), so names are plain words and none extends another by '_'.
  for (std::size_t i = 0; i < e.measures.size(); ++i) {
    const std::string& name = e.measures[i].name;
    const std::string key = "measure." + std::to_string(i) + ".name";
    if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
                            std::string::npos)
      throw ConfigError(file, key, "\"" + name + "\" must be a non-empty word of letters, digits, '_' and '-'");
    for (std::size_t j = 0; j < i; ++j) {
      const std::string& other = e.measures[j].name;
      if (name == other)
        throw ConfigError(file, key, "\"" + name + "\" is used twice; give each measure its own name");
      const std::string& longer = name.size() > other.size() ? name : other;
      const std::string& shorter = name.size() > other.size() ? other : name;
      if (longer.compare(0, shorter.size() + 1, shorter + "_") == 0)
        throw ConfigError(file, key, "\"" + name + "\" and measure " + std::to_string(j) + "'s \"" + other +
                                         "\" could name the same table (a measure's tables are <name> and <name>_<part>); rename one");
    }
  }
  if (e.kind == "micrograin") check_micrograin_directions(e);
  // [material] takes effect in brdf measures only (the geometric ones ignore it).
  if (e.materials.configured &&
      std::none_of(e.measures.begin(), e.measures.end(), [](const Measure& m) { return m.quantity == "brdf"; }))
    throw ConfigError(file, "material", "is used by brdf measures only, and this experiment has none; remove it");
  r.finish();
  return e;
}

Experiment load_experiment(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_experiment(read_input_file(path), path, overrides);
}

}  // namespace mcref
