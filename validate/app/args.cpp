#include <cerrno>
#include <cstdlib>

#include "sim/experiment/config_error.h"
#include "validate/app/verbs.h"

namespace mcref::cli {

long long parse_integer(const std::string& flag, const std::string& v, long long lo, long long hi) {
  char* end = nullptr;
  errno = 0;
  const long long n = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || *end || errno == ERANGE || n < lo || n > hi)
    throw ConfigError("command line", flag, "= " + v + " must be an integer in [" + std::to_string(lo) + ", " +
                                                 std::to_string(hi) + "]");
  return n;
}

void given_once(std::set<std::string>& seen, const std::string& name, const std::string& flag) {
  if (!seen.insert(name).second) throw ConfigError("command line", flag, "is given twice; give it once");
}

Args parse_args(const std::vector<std::string>& args, const std::string& verb, bool allow_set_and_seed) {
  Args a;
  std::set<std::string> seen;
  auto value = [&](std::size_t& i) -> const std::string& {
    if (i + 1 >= args.size()) throw ConfigError("command line", args[i], "needs a value");
    return args[++i];
  };
  auto number = [&](std::size_t& i, long long lo, long long hi) {
    const std::string& flag = args[i];
    return parse_integer(flag, value(i), lo, hi);
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& s = args[i];
    if (s == "--help" || s == "-h") a.help = true;
    else if (s == "-o" || s == "--output") given_once(seen, "-o", s), a.output = value(i);
    else if (s == "--quiet" || s == "-q") a.quiet = true;
    else if (s == "--threads" && (verb == "simulate" || verb == "validate" || verb == "dataset"))  // (the verbs that use it)
      given_once(seen, s, s), a.threads = static_cast<int>(number(i, 1, 1024));
    else if (allow_set_and_seed && s == "--seed") given_once(seen, s, s), a.seed = number(i, 0, 9223372036854775807LL);
    else if (allow_set_and_seed && s == "--set") a.sets.push_back(value(i));
    else if (verb == "validate" && s == "--force") a.force = true;
    else if (verb == "validate" && s == "--case") a.cases.push_back(value(i));
    else if (verb == "simulate" && s == "--table") a.tables.push_back(value(i));
    else if (verb == "simulate" && s == "--batch-values") a.batch_values = true;
    else if (!s.empty() && s[0] == '-') throw ConfigError("command line", s, "unknown option for 'mcref " + verb + "' (see --help)");
    else a.positional.push_back(s);
  }
  return a;
}

std::vector<std::string> with_inputs(std::vector<std::string> files, const std::vector<InputFile>& more) {
  for (const InputFile& f : more) files.push_back(f.path);
  return files;
}

}  // namespace mcref::cli
