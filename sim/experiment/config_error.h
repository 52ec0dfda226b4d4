#pragma once
// The one error type for bad user input: the CLI prints it as a single line
// naming the file, the key and the reason, and exits non-zero.
#include <stdexcept>
#include <string>

namespace mcref {

class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, const std::string& key, const std::string& reason)
      : std::runtime_error(file + (key.empty() ? "" : ": key '" + key + "'") + ": " + reason) {}
  // The message of a ConfigError formed elsewhere (e.g. on another rank).
  explicit ConfigError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace mcref
