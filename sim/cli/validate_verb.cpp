#include <cstdio>

#include "sim/cli/verbs.h"
#include "sim/config/config_error.h"

namespace mcref::cli {

int validate(const std::vector<std::string>& raw, const std::string& command_line) {
  throw ConfigError("command line", "", "validate: not built yet");
}

}  // namespace mcref::cli
