#pragma once
// Typed, range-checked reading of one TOML table. Every key read is marked;
// finish() rejects the keys nobody asked for (so typos are errors, not
// silently ignored settings). Errors are ConfigError naming file and key.
#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sim/experiment/config_error.h"

namespace mcref {

// A number as text with as many digits (at least min_digits) as it takes to
// read back the same double (messages: 100000.0001 is not shown as 100000
// beside (4, 100000]).
std::string exact_text(double v, int min_digits = 6);

struct Range {
  double lo, hi;
  bool lo_open, hi_open;
  bool contains(double x) const;
  std::string text() const;  // e.g. "(0, 1)" or "[1, inf)"
};

class TomlReader {
 public:
  TomlReader(const toml::table& table, std::string file, std::string prefix);

  bool has(const std::string& key) const;
  double number(const std::string& key, Range range, std::optional<double> fallback = std::nullopt);
  std::int64_t integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                       std::optional<std::int64_t> fallback = std::nullopt);
  std::string string(const std::string& key, const std::vector<std::string>& allowed,
                     std::optional<std::string> fallback = std::nullopt);
  std::string any_string(const std::string& key, std::optional<std::string> fallback = std::nullopt);
  bool boolean(const std::string& key, std::optional<bool> fallback = std::nullopt);
  // A number or an array of numbers, each in range; `fallback` if absent.
  std::vector<double> numbers(const std::string& key, Range range,
                              std::optional<std::vector<double>> fallback = std::nullopt);
  std::vector<std::string> strings(const std::string& key, std::vector<std::string> fallback = {});
  // Sub-table; marks the key used.
  const toml::table* table(const std::string& key);
  // Array of tables ([[key]]); marks the key used.
  std::vector<const toml::table*> tables(const std::string& key);
  // Throws on the first key that was never read.
  void finish() const;

  std::string full(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;
  const std::string& file() const { return file_; }

 private:
  const toml::node* get(const std::string& key);
  const toml::table& table_;
  std::string file_, prefix_;
  std::set<std::string> used_;
};

// Applies `key.path=value` overrides (value in TOML syntax; bare words are
// taken as strings). Array elements are addressed by index: measure.0.samples.
void apply_override(toml::table& root, const std::string& assignment, const std::string& file);

}  // namespace mcref
