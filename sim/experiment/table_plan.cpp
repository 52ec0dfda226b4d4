#include "sim/experiment/table_plan.h"

#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "models/core/vec.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/simulate_kinds.h"
#include "sim/experiment/toml_reader.h"

namespace mcref {

namespace {

struct MeasureSize {
  double cells = 0;  // of the measure's tables
  double tally = 0;  // numbers in one chunk's tally (run_chunks), per direction where directions apply
};

double count(std::size_t n) { return static_cast<double>(std::max<std::size_t>(1, n)); }

// The shapes of the tables the estimators make (sim/<kind>/), counted.
MeasureSize measure_size(const Measure& m, const Experiment& ex) {
  const std::string& q = m.quantity;
  const double dirs = count(m.theta_i.size()) * count(m.phi_i.size());
  const double normals = static_cast<double>(m.theta_m_bins) * m.phi_m_bins;
  if (q == "p1") return {double(m.r_bins), double(m.r_bins)};
  if (q == "ndf") return {normals, normals + 1};
  if (q == "tau_plus") return {dirs, 1};
  if (q == "tau_height") return {dirs * m.h_points, double(m.h_points)};
  if (q == "g1") return {dirs * (1 + normals), 2 + 2 * normals};
  if (q == "vndf") return {dirs * normals, normals + 1};
  if (q == "phase") return {double(m.mu_bins), m.mu_bins + 1.0};
  if (q == "phi_conditional")
    return {count(m.theta_i.size()) * count(m.theta_m.size()) * m.phi_bins, double(m.phi_bins)};
  if (q == "pore_visibility") {
    const double cells = count(m.theta_i.size()) * count(m.theta_o.size()) * count(m.phi.size());
    return {2 * cells, 1 + count(m.theta_i.size()) + count(m.theta_o.size()) + cells};
  }
  // brdf (sim/tally/brdf_tally.h): per hemisphere, the total and each component
  // binned, then the albedo and delta energies; components: the order-1
  // classes (spheres 1, micrograin and slab 2), order2, order3, order4plus.
  const double components = ex.kind == "spheres" ? 4 : 5;
  const double hemispheres = ex.kind == "slab" && ex.slab.substrate.kind == SlabSubstrate::Kind::kNone ? 2 : 1;
  const double bins = static_cast<double>(m.theta_o_bins) * m.phi_bins * 3;
  double cells = dirs * hemispheres * ((components + 1) * bins + 2 * (components + 1) * 3);
  cells += dirs * 3;  // slab _energy, spheres _transmittance
  if (ex.kind == "spheres") cells += count(m.theta_i.size()) * m.theta_o_bins * 3 * 3 + 3;  // _modes, _kd
  return {cells, hemispheres * (components * bins + 2 * components * 3 + 3) + 3};
}

// The keys that set a measure's size, for messages.
std::string size_keys(const Measure& m, std::size_t index) {
  const std::string k = "measure." + std::to_string(index) + ".";
  const std::string& q = m.quantity;
  std::vector<std::string> keys;
  if (q == "p1") keys = {"r_bins"};
  else if (q == "ndf") keys = {"theta_m_bins", "phi_m_bins"};
  else if (q == "phase") keys = {"mu_bins"};
  else if (q == "pore_visibility") keys = {"theta_i_deg", "theta_o_deg", "phi_deg"};
  else if (q == "phi_conditional") keys = {"theta_i_deg", "theta_m_deg", "phi_bins"};
  else if (q == "brdf") keys = {"theta_i_deg", "phi_i_deg", "theta_o_bins", "phi_bins"};
  else if (q == "tau_height") keys = {"theta_i_deg", "phi_i_deg", "h_points"};
  else if (q == "g1" || q == "vndf") keys = {"theta_i_deg", "phi_i_deg", "theta_m_bins", "phi_m_bins"};
  else keys = {"theta_i_deg", "phi_i_deg"};
  std::string text;
  for (const std::string& key : keys) text += (text.empty() ? "" : ", ") + k + key;
  return text;
}

double measure_bytes(const Measure& m, const Experiment& ex, int threads, bool keep_batch_values) {
  const MeasureSize s = measure_size(m, ex);
  return 48 * s.cells + 8 * s.tally * (threads + 2) + (keep_batch_values ? 8.0 * ex.run.batches * s.cells : 0.0);
}

// A byte count with an optional K, M, G or T suffix; -1 if malformed.
double parse_bytes(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !std::isfinite(v) || v <= 0) return -1;
  const std::string unit(end);
  const std::string units = "KMGT";
  if (unit.empty()) return v;
  const std::size_t p = unit.size() == 1 ? units.find(unit[0]) : std::string::npos;
  return p == std::string::npos ? -1 : v * std::pow(1024.0, static_cast<double>(p + 1));
}

}  // namespace

std::vector<Table> empty_tables(const Experiment& ex) {
  return flatten(ex.kind == "micrograin" ? micrograin_tables(ex) : ex.kind == "slab" ? slab_tables(ex) : sphere_tables(ex));
}

std::vector<Table> table_outline(const Experiment& ex) {
  Experiment small = ex;
  for (Measure& m : small.measures) {
    for (int* bins : {&m.theta_o_bins, &m.phi_bins, &m.mu_bins, &m.theta_m_bins, &m.phi_m_bins, &m.r_bins})
      *bins = std::min(*bins, 1);
    m.h_points = std::min(m.h_points, 2);
  }
  return empty_tables(small);
}

void check_table_names(const Experiment& ex, const std::vector<std::string>& names, const std::string& file,
                       const std::string& key) {
  if (names.empty()) return;
  const std::vector<Table> outline = table_outline(ex);
  for (const std::string& name : names)
    if (std::none_of(outline.begin(), outline.end(), [&](const Table& t) { return t.name == name; })) {
      std::string all;
      for (const Table& t : outline) all += (all.empty() ? "" : ", ") + t.name;
      throw ConfigError(file, key, "\"" + name + "\" is not a table of the experiment (it writes: " + all + ")");
    }
}

void check_table_layout(const Experiment& ex, const Table& table, const std::string& file, const std::string& key) {
  const std::vector<Table> outline = table_outline(ex);
  const auto found = std::find_if(outline.begin(), outline.end(), [&](const Table& t) { return t.name == table.name; });
  if (found == outline.end()) check_table_names(ex, {table.name}, file, key);  // throws, naming the tables it writes
  const Table& o = *found;
  const auto layout = [](const Table& t) {
    std::string s = t.quantity + " over (";
    for (std::size_t i = 0; i < t.axes.size(); ++i)
      s += (i ? ", " : "") + t.axes[i].name + " " + (t.axes[i].kind == Axis::Kind::Bins ? "bins" : "points") + " in " + t.axes[i].unit;
    return s + ")";
  };
  if (layout(table) != layout(o))
    throw ConfigError(file, key, "table \"" + table.name + "\" is " + layout(table) + ", and the experiment's is " + layout(o));
  // A polar angle outside a direction's range gives a model numbers outside its
  // domain (tau_plus_eq22 at theta_i = 2 rad: -0.63): incidence in [0, pi/2],
  // other polar angles in [0, pi] (a BTDF's theta_o); azimuths finite.
  for (const Axis& a : table.axes) {
    if (a.unit != "rad") continue;
    const bool polar = a.name.rfind("theta", 0) == 0;
    const double hi = a.name == "theta_i" ? kPi / 2 : kPi;
    for (double v : a.values)
      if (polar ? !(v >= 0 && v <= hi) : !std::isfinite(v))
        throw ConfigError(file, key, "table \"" + table.name + "\": axis " + a.name + " holds " + exact_text(v) +
                                         " rad; allowed " + (polar ? (hi < kPi ? "[0, pi/2]" : "[0, pi]") : "finite values"));
  }
}

double measure_cells(const Measure& m, const Experiment& ex) { return measure_size(m, ex).cells; }

int effective_threads(const Experiment& ex, int requested) {
  return requested > 0 ? requested : ex.run.threads > 0 ? ex.run.threads : tbb::info::default_concurrency();
}

double memory_needed(const Experiment& ex, int threads, bool keep_batch_values) {
  double bytes = 0;
  for (const Measure& m : ex.measures) bytes += measure_bytes(m, ex, threads, keep_batch_values);
  return bytes;
}

double memory_budget(std::string* why) {
  if (const char* env = std::getenv("MCREF_MEMORY_LIMIT")) {
    const double limit = parse_bytes(env);
    if (limit < 0)
      throw ConfigError("environment", "MCREF_MEMORY_LIMIT",
                        "= \"" + std::string(env) + "\" must be a positive number of bytes, optionally with K, M, G or T");
    if (why) *why = "MCREF_MEMORY_LIMIT";
    return limit;
  }
  double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  std::string source = "physical memory";
  std::ifstream cgroup("/sys/fs/cgroup/memory.max");  // cgroup v2; "max" when unlimited
  double limit = 0;
  if (cgroup >> limit && limit > 0 && limit < memory) {
    memory = limit;
    source = "cgroup memory.max";
  }
  if (why) *why = "half of the " + bytes_text(memory) + " of " + source + "; set MCREF_MEMORY_LIMIT to change it";
  return memory / 2;
}

void check_memory(const Experiment& ex, int requested_threads, bool keep_batch_values) {
  const int threads = effective_threads(ex, requested_threads);
  std::string why;
  const double budget = memory_budget(&why), need = memory_needed(ex, threads, keep_batch_values);
  if (need <= budget) return;
  std::size_t largest = 0;
  for (std::size_t k = 1; k < ex.measures.size(); ++k)
    if (measure_bytes(ex.measures[k], ex, threads, keep_batch_values) >
        measure_bytes(ex.measures[largest], ex, threads, keep_batch_values))
      largest = k;
  char cells[32];
  std::snprintf(cells, sizeof cells, "%.3g", measure_cells(ex.measures[largest], ex));
  throw ConfigError(ex.file, size_keys(ex.measures[largest], largest),
                    "the tables would need about " + bytes_text(need) + " of memory (" + cells + " cells in measure " +
                        std::to_string(largest) + ", on " + std::to_string(threads) + (threads == 1 ? " thread" : " threads") + "), more than the budget of " +
                        bytes_text(budget) + " (" + why + "); use fewer bins or directions");
}

std::string bytes_text(double bytes) {
  const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1024 && u < 5) {
    bytes /= 1024;
    ++u;
  }
  char buf[40];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return buf;
}

}  // namespace mcref
