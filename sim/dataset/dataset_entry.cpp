#include "sim/dataset/dataset_entry.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "models/core/rng.h"
#include "sim/experiment/config_error.h"
#include "sim/experiment/toml_reader.h"

namespace mcref {

namespace {

constexpr std::uint64_t kParamTag = 0x706172616dULL;  // "param"
constexpr std::uint64_t kEntryTag = 0x656e747279ULL;  // "entry"
constexpr double kPi = 3.14159265358979323846;

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  return parts;
}

bool parse_index(const std::string& s, std::size_t& idx) {
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end || v < 0) return false;
  idx = static_cast<std::size_t>(v);
  return true;
}

// Sets `value` at a dotted key path, with the semantics of --set
// (sim/experiment/toml_reader.h apply_override): missing tables are created,
// array elements are addressed by index.
void set_key(toml::table& root, const std::string& path, const toml::node& value, const std::string& file) {
  const std::vector<std::string> parts = split_path(path);
  toml::node* node = &root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const bool last = i + 1 == parts.size();
    const std::string& part = parts[i];
    if (toml::table* t = node->as_table()) {
      if (last) {
        t->insert_or_assign(part, value);
        return;
      }
      if (!t->get(part)) t->insert(part, toml::table{});
      node = t->get(part);
    } else if (toml::array* a = node->as_array()) {
      std::size_t idx = 0;
      if (!parse_index(part, idx) || idx >= a->size())
        throw ConfigError(file, path, "index '" + part + "' is not in [0, " + std::to_string(a->size()) + ")");
      if (last) {
        a->replace(a->begin() + static_cast<std::ptrdiff_t>(idx), value);
        return;
      }
      node = a->get(idx);
    } else {
      throw ConfigError(file, path, "'" + part + "' is not inside a table or array");
    }
  }
}

toml::array* find_array(toml::table& root, const std::string& path) {
  toml::node* node = &root;
  for (const std::string& part : split_path(path)) {
    std::size_t idx = 0;
    if (toml::table* t = node->as_table()) node = t->get(part);
    else if (toml::array* a = node->as_array(); a && parse_index(part, idx)) node = a->get(idx);
    else node = nullptr;
    if (!node) return nullptr;
  }
  return node->as_array();
}

// The shortest of %.15g, %.16g, %.17g that reads back as x.
std::string format_double(double x) { return exact_text(x, 15); }

// A value as --set text: numbers exact and short, anything else as TOML.
std::string value_text(const toml::node& v) {
  if (v.is_floating_point()) return format_double(*v.value<double>());
  if (const toml::array* a = v.as_array(); a && a->is_homogeneous(toml::node_type::floating_point)) {
    std::string text;
    for (const toml::node& e : *a) text += (text.empty() ? "[" : ", ") + format_double(*e.value<double>());
    return text + "]";
  }
  return toml_text(v);
}

struct Drawn {
  toml::array holder;            // one element: the value to set
  std::vector<double> columns;
};

// Value k of a grid or of choices.
Drawn pick(const DatasetParameter& p, std::size_t k) {
  Drawn d;
  d.holder.push_back(*p.values.get(k));
  d.columns = p.numeric.empty() ? std::vector<double>{static_cast<double>(k)} : p.numeric[k];
  return d;
}

// Numbers drawn: one, or an array.
Drawn numbers(std::vector<double> columns) {
  Drawn d;
  d.columns = std::move(columns);
  if (d.columns.size() == 1) {
    d.holder.push_back(d.columns[0]);
  } else {
    toml::array a;
    for (double x : d.columns) a.push_back(x);
    d.holder.push_back(a);
  }
  return d;
}

Drawn draw(const DatasetParameter& p, std::size_t grid_coord, Rng& rng) {
  using Mode = DatasetParameter::Mode;
  if (p.mode == Mode::kGrid) return pick(p, grid_coord);
  if (p.mode == Mode::kChoice) return pick(p, static_cast<std::size_t>(rng.below(p.values.size())));
  Drawn d;
  if (p.mode == Mode::kDirection) {
    const double z = rng.uniform(), phi = 2 * kPi * rng.uniform();
    const double s = std::sqrt(std::fmax(0.0, 1 - z * z));
    d.columns = {s * std::cos(phi), s * std::sin(phi), z};
  } else {
    for (int i = 0; i < p.size; ++i) {
      const double u = rng.uniform();
      d.columns.push_back(p.mode == Mode::kUniform
                              ? p.lo + (p.hi - p.lo) * u
                              : std::exp(std::log(p.lo) + (std::log(p.hi) - std::log(p.lo)) * u));
    }
  }
  return numbers(std::move(d.columns));
}

// The entry's values before they are applied: grid coordinates from the index
// (last grid parameter fastest), sampled ones from their streams.
std::vector<Drawn> draw_entry(const DatasetConfig& c, std::int64_t index) {
  std::vector<std::size_t> coord(c.parameters.size(), 0);
  std::int64_t g = index / c.per_point;
  for (std::size_t k = c.parameters.size(); k-- > 0;) {
    if (c.parameters[k].sampled()) continue;
    const auto n = static_cast<std::int64_t>(c.parameters[k].values.size());
    coord[k] = static_cast<std::size_t>(g % n);
    g /= n;
  }
  std::vector<Drawn> drawn;
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    Rng rng(stream_seed({c.seed, kParamTag, static_cast<std::uint64_t>(index), k}));
    drawn.push_back(draw(c.parameters[k], coord[k], rng));
  }
  return drawn;
}

// The base experiment with `drawn` applied.
EntryPlan apply(const DatasetConfig& c, std::int64_t index, const std::vector<Drawn>& drawn) {
  EntryPlan plan;
  plan.index = index;
  plan.seed = stream_seed({c.seed, kEntryTag, static_cast<std::uint64_t>(index)}) >> 1;
  plan.experiment = c.base;
  // Counts first: they decide which array elements exist.
  std::vector<std::pair<std::string, std::size_t>> counts;
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const DatasetParameter& p = c.parameters[k];
    if (!p.is_count()) continue;
    const auto n = static_cast<std::size_t>(*drawn[k].holder.get(0)->value<std::int64_t>());
    toml::array* a = find_array(plan.experiment, p.count_array());
    if (!a) throw ConfigError(c.file, p.key, "'" + p.count_array() + "' is not an array of the base experiment");
    while (a->size() > n) a->pop_back();
    counts.emplace_back(p.count_array(), n);
    plan.assignments.push_back(p.key + "=" + std::to_string(n));
  }
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const DatasetParameter& p = c.parameters[k];
    bool applies = true;
    for (const auto& [array, n] : counts) {
      if (p.is_count() || p.key.rfind(array + ".", 0) != 0) continue;
      std::size_t idx = 0;
      const std::string rest = p.key.substr(array.size() + 1);
      if (parse_index(rest.substr(0, rest.find('.')), idx) && idx >= n) applies = false;
    }
    if (!applies) {
      for (int i = 0; i < p.width(); ++i) plan.columns.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    plan.columns.insert(plan.columns.end(), drawn[k].columns.begin(), drawn[k].columns.end());
    if (p.is_count()) continue;
    const toml::node& value = *drawn[k].holder.get(0);
    set_key(plan.experiment, p.key, value, c.file);
    plan.assignments.push_back(p.key + "=" + value_text(value));
  }
  set_key(plan.experiment, "run.seed", toml::value<std::int64_t>(static_cast<std::int64_t>(plan.seed)), c.file);
  plan.assignments.push_back("run.seed=" + std::to_string(plan.seed));
  return plan;
}

}  // namespace

EntryPlan plan_entry(const DatasetConfig& c, std::int64_t index) { return apply(c, index, draw_entry(c, index)); }

Experiment entry_experiment(const DatasetConfig& c, const EntryPlan& plan) {
  std::ostringstream text;
  text << plan.experiment;
  Experiment ex;
  try {
    ex = parse_experiment(text.str(), c.experiment_file);
  } catch (const ConfigError& e) {
    std::string set;
    for (std::size_t i = 0; i + 1 < plan.assignments.size(); ++i) set += (set.empty() ? "" : ", ") + plan.assignments[i];
    throw ConfigError(c.file, "", "entry " + std::to_string(plan.index) + " (" + set + "): " + e.what());
  }
  // Its input files as the dataset read them (they are part of its identity).
  for (std::size_t k = 0; k < ex.inputs.size() && k < c.inputs.size(); ++k)
    if (ex.inputs[k].digest != c.inputs[k].digest)
      throw ConfigError(c.file, "", "entry " + std::to_string(plan.index) + ": '" + ex.inputs[k].path +
                                        "' changed after the dataset was read (" + c.inputs[k].digest + ", now " +
                                        ex.inputs[k].digest + "); rerun with the file as it was, or start a new output");
  return ex;
}

void check_parameter_values(const DatasetConfig& c) {
  using Mode = DatasetParameter::Mode;
  // Entry 0's values, with every count at its largest so that every parameter applies.
  std::vector<Drawn> others = draw_entry(c, 0);
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const DatasetParameter& p = c.parameters[k];
    if (!p.is_count()) continue;
    std::size_t widest = 0;
    for (std::size_t i = 0; i < p.values.size(); ++i)
      if (*p.values.get(i)->value<std::int64_t>() > *p.values.get(widest)->value<std::int64_t>()) widest = i;
    others[k] = pick(p, widest);
  }
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const DatasetParameter& p = c.parameters[k];
    std::vector<std::pair<std::string, Drawn>> probes;  // what the value is, the value
    if (p.mode == Mode::kGrid || p.mode == Mode::kChoice)
      for (std::size_t i = 0; i < p.values.size(); ++i) probes.emplace_back(p.mode == Mode::kGrid ? "values" : "choices", pick(p, i));
    if (p.mode == Mode::kUniform || p.mode == Mode::kLogUniform) {
      probes.emplace_back("the lower end of range", numbers(std::vector<double>(p.size, p.lo)));
      probes.emplace_back("the upper end of range", numbers(std::vector<double>(p.size, p.hi)));
    }
    for (const auto& [what, value] : probes) {
      std::vector<Drawn> drawn = others;
      drawn[k] = value;
      std::ostringstream text;
      text << apply(c, 0, drawn).experiment;
      try {
        parse_experiment(text.str(), c.experiment_file);
      } catch (const ConfigError& e) {
        // The error may be another parameter's, at its entry-0 value: blame that one.
        const std::string message = e.what();
        for (std::size_t q = 0; q < c.parameters.size(); ++q)
          if (q != k && message.find("key '" + c.parameters[q].key + "'") != std::string::npos)
            throw ConfigError(c.file, c.parameters[q].key, value_text(*drawn[q].holder.get(0)) +
                                                               " (as drawn for entry 0) makes an invalid experiment: " + message);
        throw ConfigError(c.file, p.key, value_text(*value.holder.get(0)) + " (" + what + ") makes an invalid experiment, the other parameters as in entry 0: " + message);
      }
    }
  }
}

}  // namespace mcref
