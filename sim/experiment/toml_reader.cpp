#include "sim/experiment/toml_reader.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace mcref {

std::string exact_text(double v, int min_digits) {
  char buf[32];
  for (int digits = min_digits; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

namespace {

// What a value of the wrong type is, for messages: "the string \"a\"", "true".
std::string given(const toml::node& n) {
  if (const auto* s = n.as_string()) return "the string \"" + s->get() + "\"";
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* d = n.as_floating_point()) return exact_text(d->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (n.is_array()) return "an array";
  if (n.is_table()) return "a table";
  return "a date or time";
}

}  // namespace

bool Range::contains(double x) const {
  if (!std::isfinite(x)) return false;
  const bool above = lo_open ? x > lo : x >= lo;
  const bool below = hi_open ? x < hi : x <= hi;
  return above && below;
}

std::string Range::text() const {
  auto num = [](double v) {
    if (std::isinf(v)) return std::string(v > 0 ? "inf" : "-inf");
    return exact_text(v);
  };
  return std::string(lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
}

TomlReader::TomlReader(const toml::table& table, std::string file, std::string prefix)
    : table_(table), file_(std::move(file)), prefix_(std::move(prefix)) {}

void TomlReader::fail(const std::string& key, const std::string& reason) const {
  throw ConfigError(file_, full(key), reason);
}

bool TomlReader::has(const std::string& key) const { return table_.contains(key); }

const toml::node* TomlReader::get(const std::string& key) {
  used_.insert(key);
  return table_.get(key);
}

double TomlReader::number(const std::string& key, Range range, std::optional<double> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (a number in " + range.text() + ")");
  }
  std::optional<double> v = n->value<double>();
  if (!v) fail(key, "must be a number in " + range.text() + ", not " + given(*n));
  if (!range.contains(*v)) fail(key, "= " + exact_text(*v) + " is out of range; allowed " + range.text());
  return *v;
}

std::int64_t TomlReader::integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                                 std::optional<std::int64_t> fallback) {
  const std::string allowed = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (" + allowed + ")");
  }
  std::optional<std::int64_t> v = n->value_exact<std::int64_t>();
  if (!v) {
    // Accept integral floats such as 1e6.
    std::optional<double> d = n->value_exact<double>();
    if (d && std::floor(*d) == *d && std::fabs(*d) < 9e18) v = static_cast<std::int64_t>(*d);
  }
  if (!v) fail(key, "must be " + allowed + ", not " + given(*n));
  if (*v < lo || *v > hi) fail(key, "= " + std::to_string(*v) + " is out of range; allowed " + allowed);
  return *v;
}

std::string TomlReader::string(const std::string& key, const std::vector<std::string>& allowed,
                               std::optional<std::string> fallback) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("\"" + a + "\"");
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (one of " + list + ")");
  }
  std::optional<std::string> v = n->value<std::string>();
  if (!v) fail(key, "must be a string, one of " + list);
  for (const auto& a : allowed)
    if (*v == a) return *v;
  fail(key, "= \"" + *v + "\" is not known; allowed: " + list);
}

std::string TomlReader::any_string(const std::string& key, std::optional<std::string> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (a string)");
  }
  std::optional<std::string> v = n->value<std::string>();
  if (!v) fail(key, "must be a string");
  return *v;
}

bool TomlReader::boolean(const std::string& key, std::optional<bool> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (true or false)");
  }
  std::optional<bool> v = n->value_exact<bool>();  // 1 and 0 are not booleans
  if (!v) fail(key, "must be true or false");
  return *v;
}

std::vector<double> TomlReader::numbers(const std::string& key, Range range,
                                        std::optional<std::vector<double>> fallback) {
  const toml::node* n = get(key);
  if (!n) {
    if (fallback) return *fallback;
    fail(key, "is required (a number or a list of numbers in " + range.text() + ")");
  }
  std::vector<double> out;
  auto take = [&](const toml::node& x) {
    std::optional<double> v = x.value<double>();
    if (!v) fail(key, "must hold numbers in " + range.text() + ", not " + given(x));
    if (!range.contains(*v)) fail(key, "holds " + exact_text(*v) + ", out of range; allowed " + range.text());
    out.push_back(*v);
  };
  if (const toml::array* a = n->as_array()) {
    for (const toml::node& x : *a) take(x);
  } else {
    take(*n);
  }
  if (out.empty()) fail(key, "must not be empty");
  return out;
}

std::vector<std::string> TomlReader::strings(const std::string& key, std::vector<std::string> fallback) {
  const toml::node* n = get(key);
  if (!n) return fallback;
  std::vector<std::string> out;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be a list of strings");
  for (const toml::node& x : *a) {
    std::optional<std::string> v = x.value<std::string>();
    if (!v) fail(key, "must be a list of strings");
    out.push_back(*v);
  }
  return out;
}

const toml::table* TomlReader::table(const std::string& key) {
  const toml::node* n = get(key);
  if (!n) return nullptr;
  const toml::table* t = n->as_table();
  if (!t) fail(key, "must be a table");
  return t;
}

std::vector<const toml::table*> TomlReader::tables(const std::string& key) {
  std::vector<const toml::table*> out;
  const toml::node* n = get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be an array of tables ([[" + full(key) + "]])");
  for (const toml::node& x : *a) {
    const toml::table* t = x.as_table();
    if (!t) fail(key, "must be an array of tables ([[" + full(key) + "]])");
    out.push_back(t);
  }
  return out;
}

void TomlReader::finish() const {
  for (auto&& [k, v] : table_) {
    const std::string key(k.str());
    if (!used_.count(key)) fail(key, "is not a known key here");
  }
}

void apply_override(toml::table& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError(file, assignment, "--set needs key=value (e.g. geometry.tau0=0.3)");
  const std::string path = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  // Parse the value as TOML; a bare word that does not parse is a string.
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"v", text}};
  }
  toml::node* value = parsed.get("v");
  // Walk the path.
  toml::node* node = &root;
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const bool last = i + 1 == parts.size();
    const std::string& part = parts[i];
    if (toml::table* t = node->as_table()) {
      if (last) {
        t->insert_or_assign(part, *value);
        return;
      }
      toml::node* next = t->get(part);
      if (!next) {
        t->insert(part, toml::table{});
        next = t->get(part);
      }
      node = next;
    } else if (toml::array* a = node->as_array()) {
      char* end = nullptr;
      const long idx = std::strtol(part.c_str(), &end, 10);
      if (*end || idx < 0 || static_cast<std::size_t>(idx) >= a->size())
        throw ConfigError(file, path, "index '" + part + "' is not in [0, " + std::to_string(a->size()) + ")");
      if (last) {
        a->replace(a->begin() + idx, *value);
        return;
      }
      node = a->get(static_cast<std::size_t>(idx));
    } else {
      throw ConfigError(file, path, "'" + part + "' is not inside a table or array");
    }
  }
}

}  // namespace mcref
