#include "sim/dataset/dataset_config.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "sim/experiment/toml_reader.h"
#include "sim/files/input_file.h"
#include "sim/hdf5/file_seal.h"

namespace mcref {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

toml::table parse_toml(const std::string& text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& err) {
    std::ostringstream s;
    s << "line " << err.source().begin.line << ": " << err.description();
    throw ConfigError(file, "", "TOML syntax error at " + s.str());
  }
}

// Numbers of one value: a number, or an array of numbers; empty otherwise.
std::vector<double> as_numbers(const toml::node& n) {
  if (n.is_number()) return {n.value<double>().value()};
  const toml::array* a = n.as_array();
  if (!a || a->empty()) return {};
  std::vector<double> v;
  for (const toml::node& e : *a) {
    if (!e.is_number()) return {};
    v.push_back(e.value<double>().value());
  }
  return v;
}

// values / choices: numeric columns if every value is a number or every value
// an array of numbers of one length; categorical labels otherwise.
void read_values(DatasetParameter& p, const toml::array& a, TomlReader& r, const std::string& key) {
  if (a.empty()) r.fail(key, "needs at least one value");
  p.values = a;
  std::vector<std::vector<double>> numeric;
  for (const toml::node& n : a) {
    numeric.push_back(as_numbers(n));
    if (numeric.back().empty() || numeric.back().size() != numeric.front().size()) {
      numeric.clear();
      break;
    }
  }
  p.numeric = numeric;
  if (p.numeric.empty())
    for (const toml::node& n : a) p.labels.push_back(n.is_string() ? n.value<std::string>().value() : toml_text(n));
}

// The node at a dotted key path (array elements by index), or nullptr.
const toml::node* find_path(const toml::table& root, const std::string& path) {
  const toml::node* node = &root;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) {
    if (const toml::table* t = node->as_table()) {
      node = t->get(part);
    } else if (const toml::array* a = node->as_array()) {
      char* end = nullptr;
      const long idx = std::strtol(part.c_str(), &end, 10);
      node = (*end || part.empty() || idx < 0) ? nullptr : a->get(static_cast<std::size_t>(idx));
    } else {
      node = nullptr;
    }
    if (!node) return nullptr;
  }
  return node;
}

DatasetParameter read_parameter(const toml::table& t, const DatasetConfig& c, std::size_t index) {
  const std::string prefix = "parameter." + std::to_string(index);
  TomlReader r(t, c.file, prefix);
  static const std::set<std::string> allowed{"key", "values", "choices", "range", "distribution", "size"};
  for (const auto& [k, v] : t)
    if (!allowed.count(std::string(k.str())))
      throw ConfigError(c.file, prefix + "." + std::string(k.str()),
                        "is not a parameter key (allowed: key, values, choices, range, distribution, size)");
  DatasetParameter p;
  p.key = r.any_string("key");
  if (p.key.empty() || p.key.front() == '.' || p.key.back() == '.' || p.key.find("..") != std::string::npos)
    r.fail("key", "must be an experiment key path such as \"geometry.layer.0.alpha\"");
  if (p.key == "geometry.density_vdb")
    r.fail("key", "a dataset cannot vary geometry.density_vdb (the files' contents would not be part of its identity); "
                  "set it in the base experiment");
  if (p.key == "run.seed")
    r.fail("key", "a dataset sets every entry's run.seed itself, from [dataset] seed and the entry's index; "
                  "vary [dataset] seed instead");
  const int given = (t.contains("values") ? 1 : 0) + (t.contains("choices") ? 1 : 0) + (t.contains("range") ? 1 : 0);
  const std::string dist = r.string("distribution", {"uniform", "log_uniform", "direction"}, std::string(""));
  if (given != 1 && dist != "direction")
    r.fail("values", "give exactly one of values = [...] (grid), choices = [...] or range = [lo, hi] (sampled)");
  if (dist == "direction" && given != 0)
    r.fail("distribution", "\"direction\" takes no values, choices or range");
  if (!dist.empty() && !t.contains("range") && dist != "direction")
    r.fail("distribution", "\"" + dist + "\" needs range = [lo, hi]");
  if (t.contains("values") || t.contains("choices")) {
    const std::string key = t.contains("values") ? "values" : "choices";
    const toml::array* a = t.get(key)->as_array();
    if (!a) r.fail(key, "must be an array of values");
    p.mode = key == "values" ? DatasetParameter::Mode::kGrid : DatasetParameter::Mode::kChoice;
    read_values(p, *a, r, key);
  } else if (t.contains("range")) {
    const std::vector<double> range = r.numbers("range", {-kInf, kInf, true, true});
    if (range.size() != 2 || !(range[0] < range[1])) r.fail("range", "takes [lo, hi] with lo < hi");
    p.lo = range[0];
    p.hi = range[1];
    p.mode = dist == "log_uniform" ? DatasetParameter::Mode::kLogUniform : DatasetParameter::Mode::kUniform;
    if (p.mode == DatasetParameter::Mode::kLogUniform && !(p.lo > 0))
      r.fail("range", "log_uniform needs 0 < lo < hi (got lo = " + std::to_string(p.lo) + ")");
    p.size = static_cast<int>(r.integer("size", 1, 64, 1));
  } else {
    p.mode = DatasetParameter::Mode::kDirection;
    p.size = 3;
  }
  if (t.contains("size") && p.mode != DatasetParameter::Mode::kUniform && p.mode != DatasetParameter::Mode::kLogUniform)
    r.fail("size", "applies to range = [lo, hi] only");
  if (p.is_count()) {
    const toml::node* arr = find_path(c.base, p.count_array());
    if (!arr || !arr->as_array() || arr->as_array()->empty())
      r.fail("key", "\"" + p.key + "\" needs '" + p.count_array() + "' to be an array in the base experiment " +
                        c.experiment_file);
    const std::size_t len = arr->as_array()->size();
    const std::string allowed_range = "[1, " + std::to_string(len) + "]";
    if (p.mode != DatasetParameter::Mode::kGrid && p.mode != DatasetParameter::Mode::kChoice)
      r.fail("key", "a count takes values = [...] or choices = [...], integers in " + allowed_range);
    for (const toml::node& n : p.values)
      if (!n.is_integer() || *n.value<std::int64_t>() < 1 || static_cast<std::size_t>(*n.value<std::int64_t>()) > len)
        r.fail(p.mode == DatasetParameter::Mode::kGrid ? "values" : "choices",
               "= " + toml_text(n) + ": counts of '" + p.count_array() + "' must be integers in " + allowed_range);
  }
  return p;
}

}  // namespace

std::string toml_text(const toml::node& node) {
  std::ostringstream s;
  if (const toml::table* t = node.as_table()) {
    toml::table copy = *t;
    copy.is_inline(true);
    toml::table wrap{{"v", copy}};
    s << wrap;
    std::string text = s.str();
    return text.size() > 4 && text.rfind("v = ", 0) == 0 ? text.substr(4) : text;
  }
  node.visit([&](const auto& n) { s << n; });
  return s.str();
}

bool DatasetParameter::is_count() const {
  return key.size() > 6 && key.compare(key.size() - 6, 6, ".count") == 0;
}

std::string DatasetParameter::count_array() const { return key.substr(0, key.size() - 6); }

int DatasetParameter::width() const {
  if (mode == Mode::kGrid || mode == Mode::kChoice) return numeric.empty() ? 1 : static_cast<int>(numeric[0].size());
  return size;
}

std::vector<std::string> DatasetParameter::column_names() const {
  const int n = width();
  const bool array = mode == Mode::kDirection || size > 1 ||
                     ((mode == Mode::kGrid || mode == Mode::kChoice) && !numeric.empty() && values[0].is_array());
  if (!array) return {key};
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back(key + "[" + std::to_string(i) + "]");
  return names;
}

std::int64_t DatasetConfig::grid_points() const {
  std::int64_t n = 1;
  for (const DatasetParameter& p : parameters)
    if (!p.sampled()) n *= static_cast<std::int64_t>(p.values.size());
  return n;
}

std::vector<std::string> DatasetConfig::column_names() const {
  std::vector<std::string> names;
  for (const DatasetParameter& p : parameters)
    for (const std::string& n : p.column_names()) names.push_back(n);
  return names;
}

DatasetConfig parse_dataset(const std::string& text, const std::string& file) {
  DatasetConfig c;
  c.file = file;
  const toml::table root = parse_toml(text, file);
  std::ostringstream canonical;
  canonical << root;
  c.text = canonical.str();
  TomlReader r(root, file, "");
  const toml::table* d = r.table("dataset");
  if (!d) r.fail("dataset", "is required ([dataset] with experiment = \"base.toml\")");
  TomlReader dr(*d, file, "dataset");
  c.experiment = dr.any_string("experiment");
  c.experiment_file = path_beside(file, c.experiment);
  c.base = parse_toml(read_input_file(c.experiment_file, file, "dataset.experiment"), c.experiment_file);
  std::ostringstream base_canonical;
  base_canonical << c.base;
  c.experiment_text = base_canonical.str();
  // An input file's content is part of the dataset's identity (shards and resumes compare it),
  // with its path as written (relative to the base experiment), whatever the working directory.
  if (const toml::node* vdb = find_path(c.base, "geometry.density_vdb"); vdb && vdb->is_string()) {
    const std::string given = *vdb->value<std::string>();
    InputFile in{path_beside(c.experiment_file, given), ""};
    in.digest = content_digest(read_input_file(in.path, c.experiment_file, "geometry.density_vdb"));
    c.experiment_text += input_provenance("geometry.density_vdb", given, in.digest);
    c.inputs.push_back(in);
  }
  c.seed = static_cast<std::uint64_t>(dr.integer("seed", 0, std::numeric_limits<std::int64_t>::max(), 1));
  const bool has_entries = dr.has("entries");
  c.per_point = dr.integer("entries", 1, std::int64_t(1) << 40, 1);
  c.tables = dr.strings("tables");
  for (std::size_t i = 0; i < c.tables.size(); ++i)
    if (std::find(c.tables.begin(), c.tables.begin() + i, c.tables[i]) != c.tables.begin() + i)
      throw ConfigError(file, "dataset.tables", "names \"" + c.tables[i] + "\" twice");
  c.compression = static_cast<int>(dr.integer("compression", 0, 9, 0));
  dr.finish();
  const auto params = r.tables("parameter");
  std::set<std::string> keys;
  bool sampled = false;
  constexpr std::int64_t kMaxEntries = std::int64_t(1) << 40;
  std::int64_t grid = 1;  // checked at each factor: the product of a few large grids wraps
  for (std::size_t i = 0; i < params.size(); ++i) {
    c.parameters.push_back(read_parameter(*params[i], c, i));
    if (!c.parameters.back().sampled()) {
      const auto size = static_cast<std::int64_t>(c.parameters.back().values.size());
      if (size > kMaxEntries / grid)
        throw ConfigError(file, "parameter." + std::to_string(i) + ".values",
                          "makes the grid hold more than 2^40 points (" + std::to_string(grid) + " before it, times " +
                              std::to_string(size) + ")");
      grid *= size;
    }
    if (!keys.insert(c.parameters.back().key).second)
      throw ConfigError(file, "parameter." + std::to_string(i) + ".key",
                        "\"" + c.parameters.back().key + "\" is varied twice; give each key one [[parameter]]");
    sampled = sampled || c.parameters.back().sampled();
  }
  if (sampled && !has_entries)
    throw ConfigError(file, "dataset.entries", "is required with sampled parameters (an integer in [1, 2^40])");
  if (!sampled && has_entries && c.per_point != 1)
    throw ConfigError(file, "dataset.entries", "applies to sampled parameters (range, choices, direction); "
                                               "a pure grid has one entry per grid point");
  if (c.grid_points() > kMaxEntries / c.per_point)
    throw ConfigError(file, "dataset.entries", "the dataset would hold more than 2^40 entries");
  r.finish();
  return c;
}

DatasetConfig load_dataset(const std::string& path) { return parse_dataset(read_input_file(path), path); }

}  // namespace mcref
